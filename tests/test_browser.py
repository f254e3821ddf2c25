"""JupyterLab, as the setup installs it, opens the notebooks' .py sources as notebooks.

Starts the project's JupyterLab on 127.0.0.1 (a free port, a token, settings and workspaces in
a temporary folder so the user's own settings play no part) and, in headless Chromium driven by
playwright, checks that the file browser lists each notebook of ``notebooks/`` once (its .py;
the generated .ipynb is hidden by the server config ``make setup`` installs), and that
``notebooks/02_scene.py`` opens as a notebook (not in the text editor) with the outputs of its
paired .ipynb and is not marked modified once its kernel has started. The server is stopped by
its PID. Needs Debian's ``chromium`` and the ``playwright`` package (``make setup`` installs
both; playwright's own browser download is never used).

Why a notebook showed as modified when opened: JupyterLab writes the running kernel's
``kernelspec`` and ``language_info`` into the notebook as its kernel starts; where they differ
from what was read (the headers said ``display_name: Python 3``, ipykernel's spec says
``Python 3 (ipykernel)``; ``jupytext --to ipynb`` writes no ``language_info``) the notebook is
changed. The tests without a browser check both against this environment's kernel.
"""

from __future__ import annotations

import collections
import json
import os
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import psutil
import pytest

REPO = Path(__file__).resolve().parent.parent
CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
OVERRIDES = Path(sys.prefix, "share", "jupyter", "lab", "settings", "overrides.d", "docking.json")
SERVER_CONFIG = Path(sys.prefix, "etc", "jupyter", "jupyter_server_config.json")
NOTEBOOKS = sorted((REPO / "notebooks").glob("[0-9]*.py"))


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def jupyterlab(tmp_path):
    """A running JupyterLab server: yields ``(base_url, token)``; stopped by PID afterwards."""
    if not OVERRIDES.exists():
        pytest.fail(
            f"{OVERRIDES} is missing: `make setup` installs jupyterlab/overrides.json there"
        )
    if not SERVER_CONFIG.exists():
        pytest.fail(
            f"{SERVER_CONFIG} is missing: `make setup` installs "
            "jupyterlab/jupyter_server_config.json there"
        )
    port, token = _free_port(), secrets.token_hex(16)
    env = {
        **os.environ,
        "JUPYTERLAB_SETTINGS_DIR": str(tmp_path / "user-settings"),
        "JUPYTERLAB_WORKSPACES_DIR": str(tmp_path / "workspaces"),
        "JUPYTER_RUNTIME_DIR": str(tmp_path / "runtime"),
    }
    log = open(tmp_path / "jupyterlab.log", "wb")
    server = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "jupyterlab",
            "--no-browser",
            "--ip=127.0.0.1",
            f"--port={port}",
            "--ServerApp.port_retries=0",
            f"--IdentityProvider.token={token}",
            f"--ServerApp.root_dir={REPO}",
            "--ServerApp.allow_root=True",  # CI runs as root
        ],
        env=env,
        stdout=log,
        stderr=subprocess.STDOUT,
    )
    base = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 60
        while True:
            if server.poll() is not None:
                pytest.fail(f"JupyterLab exited: {(tmp_path / 'jupyterlab.log').read_text()}")
            try:
                with urllib.request.urlopen(f"{base}/api/status?token={token}", timeout=2):
                    break
            except OSError:
                if time.monotonic() > deadline:
                    pytest.fail("JupyterLab did not answer within 60 s")
                time.sleep(0.5)
        yield base, token
    finally:
        _stop(server)
        log.close()


def _stop(server: subprocess.Popen) -> None:
    """SIGTERM to the server's PID; it shuts its kernels down. Asserts nothing is left."""
    try:
        children = psutil.Process(server.pid).children(recursive=True)  # kernels
    except psutil.NoSuchProcess:
        children = []
    if server.poll() is None:
        os.kill(server.pid, signal.SIGTERM)
        try:
            server.wait(timeout=30)
        except subprocess.TimeoutExpired:
            os.kill(server.pid, signal.SIGKILL)
            server.wait(timeout=10)
    _, alive = psutil.wait_procs(children, timeout=10)
    assert not psutil.pid_exists(server.pid)
    assert not alive, f"processes left by JupyterLab: {alive}"


def _browser(p):
    assert Path(CHROMIUM).exists(), "Debian's chromium is missing: `make setup` installs it"
    return p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)


def _screenshot(page, path: Path) -> None:
    page.screenshot(path=str(path))
    shot = os.environ.get("DOCKING_BROWSER_SCREENSHOT")
    if shot:
        page.screenshot(path=shot)


def _header_kernelspec(source: Path) -> dict:
    jupytext = pytest.importorskip("jupytext")
    return jupytext.read(source).metadata.get("kernelspec", {})


@pytest.mark.parametrize("source", NOTEBOOKS, ids=lambda path: path.name)
def test_header_kernelspec_is_the_installed_kernels(source):
    """JupyterLab writes the kernel's spec into the notebook as the kernel starts: a header
    that names it otherwise is changed (and the notebook marked modified) on opening."""
    kernelspec = pytest.importorskip("jupyter_client.kernelspec")
    header = _header_kernelspec(source)
    spec = kernelspec.KernelSpecManager().get_kernel_spec(header.get("name", "python3"))
    expected = {"display_name": spec.display_name, "language": spec.language}
    assert {key: header.get(key) for key in expected} == expected, (
        f"{source.name}'s jupytext header: its kernelspec should be {expected}"
    )


@pytest.mark.slow
def test_generated_ipynb_carries_the_kernels_language_info():
    """`make notebooks` writes jupyterlab/kernel_metadata.py's language_info into each .ipynb;
    it must be what the kernel reports, or JupyterLab rewrites it when the kernel starts."""
    manager = pytest.importorskip("jupyter_client.manager")
    written = json.loads(
        subprocess.run(
            [sys.executable, str(REPO / "jupyterlab" / "kernel_metadata.py")],
            check=True,
            capture_output=True,
            text=True,
        ).stdout
    )
    km, kc = manager.start_new_kernel(kernel_name="python3")
    try:
        kc.kernel_info()
        reply = kc.get_shell_msg(timeout=30)
        while reply["msg_type"] != "kernel_info_reply":
            reply = kc.get_shell_msg(timeout=30)
    finally:
        kc.stop_channels()
        km.shutdown_kernel()
    assert not km.is_alive()
    assert written == {"language_info": reply["content"]["language_info"]}


@pytest.mark.slow
def test_lab_lists_each_notebook_once(jupyterlab, tmp_path):
    playwright = pytest.importorskip("playwright.sync_api")
    hidden = sorted(path.with_suffix(".ipynb").name for path in NOTEBOOKS)
    on_disk = [name for name in hidden if (REPO / "notebooks" / name).exists()]
    assert on_disk, "no generated .ipynb in notebooks/ to hide: run `make notebooks`"
    base, token = jupyterlab
    with playwright.sync_playwright() as p:
        browser = _browser(p)
        try:
            page = browser.new_page(viewport={"width": 1280, "height": 900})
            page.goto(f"{base}/lab/tree/notebooks?token={token}")
            items = page.locator(".jp-DirListing-content .jp-DirListing-itemText")
            page.locator(".jp-BreadCrumbs", has_text="notebooks").wait_for(timeout=90_000)
            items.filter(has_text=NOTEBOOKS[0].name).wait_for(timeout=30_000)
            _screenshot(page, tmp_path / "notebooks_listing.png")
            listed = [text.strip() for text in items.all_inner_texts()]
        finally:
            browser.close()
    assert all(path.name in listed for path in NOTEBOOKS), listed
    assert not [name for name in listed if name.endswith(".ipynb")], listed
    stems = collections.Counter(Path(name).stem for name in listed)
    assert all(stems[path.stem] == 1 for path in NOTEBOOKS), listed


@pytest.mark.slow
def test_lab_opens_py_notebook_as_notebook(jupyterlab, tmp_path):
    """02_scene.py opens in a notebook panel, shows its paired .ipynb's outputs (read through
    jupytext while the .ipynb is hidden), and once its kernel is idle it is not modified."""
    playwright = pytest.importorskip("playwright.sync_api")
    nbformat = pytest.importorskip("nbformat")
    paired = REPO / "notebooks" / "02_scene.ipynb"
    if not paired.exists():
        pytest.fail(f"{paired} is missing: `make notebooks` generates it, `make test` runs it")
    outputs = sum(len(cell.get("outputs", [])) for cell in nbformat.read(paired, 4).cells)
    if not outputs:
        pytest.fail(f"{paired} holds no outputs: `make test` executes it")
    base, token = jupyterlab
    with playwright.sync_playwright() as p:
        browser = _browser(p)
        try:
            page = browser.new_page(viewport={"width": 1280, "height": 900})
            page.goto(f"{base}/lab/tree/notebooks/02_scene.py?token={token}")
            cells = page.locator(".jp-Notebook .jp-Cell")
            page.wait_for_function(
                "document.querySelectorAll('.jp-Notebook .jp-Cell').length > 5", timeout=90_000
            )
            heading = page.locator(".jp-Notebook .jp-MarkdownOutput h1").first
            heading.wait_for(timeout=30_000)
            # Settled: the kernel has started and is idle (JupyterLab has written its spec
            # and language_info into the notebook by then), and a few seconds more.
            page.locator(".jp-StatusBar-Widget", has_text="| Idle").wait_for(timeout=90_000)
            page.wait_for_timeout(3_000)
            figure = page.locator(".jp-Notebook .jp-OutputArea-output img").first
            figure.scroll_into_view_if_needed()
            page.wait_for_timeout(1_000)  # the notebook renders the cells scrolled to
            _screenshot(page, tmp_path / "02_scene.png")
            assert cells.count() > 5
            assert "02" in heading.inner_text()
            # The document is open in a notebook panel, not in the file editor.
            assert page.locator(".jp-FileEditor:visible").count() == 0
            # The paired .ipynb's outputs, Fig. 2's image among them.
            assert page.locator(".jp-Notebook .jp-OutputArea-output").count() == outputs
            assert figure.is_visible()
            # Not modified: no dirty mark on its tab (nor anywhere else).
            tab = page.locator(".lm-TabBar-tab", has_text="02_scene.py")
            assert tab.count() == 1
            assert "jp-mod-dirty" not in (tab.get_attribute("class") or "")
            assert page.locator(".jp-mod-dirty").count() == 0
        finally:
            browser.close()
