"""Shared fixtures: an isolated schema environment and paths to the shared reference data."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"
SHARED_SCHEMAS = SHARED / "schemas"
CORPUS_RAIL = SHARED / "corpus" / "rail"

needs_shared = pytest.mark.skipif(
    not SHARED_SCHEMAS.is_dir(), reason="../shared (official ASAM schemas, corpus) is absent"
)


@pytest.fixture(autouse=True)
def isolated_schemas(
    tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch
) -> Iterator[Path]:
    """No test sees the developer's schemas: empty user data folder, no schema path."""
    data = tmp_path_factory.mktemp("xodrlint-data")
    monkeypatch.setenv("XODRLINT_DATA_DIR", str(data))
    monkeypatch.setenv("XODRLINT_CACHE_DIR", str(tmp_path_factory.mktemp("xodrlint-cache")))
    monkeypatch.delenv("XODRLINT_SCHEMA_PATH", raising=False)
    monkeypatch.delenv("XODRLINT_DEBUG", raising=False)
    yield data
