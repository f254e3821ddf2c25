"""Shared test setup."""

import pytest


@pytest.fixture(autouse=True)
def _no_committed_ledger(monkeypatch):
    """Unit tests compute the runs they check: the committed ledger (which the notebooks
    read) is off unless a test points DOCKING_LEDGER at a ledger of its own."""
    monkeypatch.setenv("DOCKING_LEDGER", "off")


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(items):
    """Mark the notebooks nbmake collects ``notebook``, before ``-m`` selects (``-m notebook``
    runs them alone). make test runs them in one session with the unit and slow tests
    (``-m "not docs"``), so that neither of its two processes waits while the other executes
    the longest notebook."""
    for item in items:
        if type(item).__module__.startswith("nbmake"):
            item.add_marker(pytest.mark.notebook)
