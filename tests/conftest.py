"""Shared test setup."""

import pytest


@pytest.fixture(autouse=True)
def _no_committed_ledger(monkeypatch):
    """Unit tests compute the runs they check: the committed ledger (which the notebooks
    read) is off unless a test points DOCKING_LEDGER at a ledger of its own."""
    monkeypatch.setenv("DOCKING_LEDGER", "off")
