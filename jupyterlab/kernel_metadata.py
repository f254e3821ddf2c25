"""Print the notebook metadata that this environment's Python kernel reports, as JSON.

``make notebooks`` passes it to ``jupytext --update-metadata``: JupyterLab writes the kernel's
``language_info`` into a notebook as its kernel starts, so a generated ``.ipynb`` without it
(jupytext writes none) would show as modified as soon as it is opened.
"""

import json

from ipykernel.ipkernel import IPythonKernel

print(json.dumps({"language_info": IPythonKernel.language_info}))
