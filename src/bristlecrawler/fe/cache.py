"""JAX persistent compilation cache for the FE programs.

Compiling a step for a new topology takes seconds; the cache keeps the XLA executables on
disk between runs. Default folder ``~/.cache/bristlecrawler/jax`` (or ``$XDG_CACHE_HOME``);
set ``BRISTLECRAWLER_NO_JAX_CACHE=1`` to opt out, ``BRISTLECRAWLER_JAX_CACHE=path`` to move.
"""

from __future__ import annotations

import os
from pathlib import Path


def enable_compilation_cache(path: str | os.PathLike | None = None) -> Path | None:
    """Point JAX's persistent cache at ``path``; returns the folder, or None if opted out."""
    if os.environ.get("BRISTLECRAWLER_NO_JAX_CACHE", "").strip() not in ("", "0"):
        return None
    import jax

    if path is None:
        path = os.environ.get("BRISTLECRAWLER_JAX_CACHE")
    if path is None:
        base = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache"))
        path = base / "bristlecrawler" / "jax"
    folder = Path(path).expanduser()
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return None
    jax.config.update("jax_compilation_cache_dir", str(folder))
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.5)
    return folder
