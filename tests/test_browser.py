"""JupyterLab, as the setup installs it, opens the notebooks' .py sources as notebooks.

Starts the project's JupyterLab on 127.0.0.1 (a free port, a token, settings and workspaces in
a temporary folder so the user's own settings play no part), opens ``notebooks/02_scene.py`` in
headless Chromium driven by playwright, checks that notebook cells are shown (not the text
editor), and stops the server by its PID. Needs Debian's ``chromium`` and the ``playwright``
package (``make setup`` installs both; playwright's own browser download is never used).
"""

from __future__ import annotations

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


@pytest.mark.slow
def test_lab_opens_py_notebook_as_notebook(jupyterlab, tmp_path):
    playwright = pytest.importorskip("playwright.sync_api")
    assert Path(CHROMIUM).exists(), "Debian's chromium is missing: `make setup` installs it"
    base, token = jupyterlab
    with playwright.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1280, "height": 900})
            page.goto(f"{base}/lab/tree/notebooks/02_scene.py?token={token}")
            cells = page.locator(".jp-Notebook .jp-Cell")
            page.wait_for_function(
                "document.querySelectorAll('.jp-Notebook .jp-Cell').length > 5", timeout=90_000
            )
            heading = page.locator(".jp-Notebook .jp-MarkdownOutput h1").first
            heading.wait_for(timeout=30_000)
            page.screenshot(path=str(tmp_path / "02_scene.png"))
            shot = os.environ.get("DOCKING_BROWSER_SCREENSHOT")
            if shot:
                page.screenshot(path=shot)
            assert cells.count() > 5
            assert "02" in heading.inner_text()
            # The document is open in a notebook panel, not in the file editor.
            assert page.locator(".jp-FileEditor:visible").count() == 0
        finally:
            browser.close()
