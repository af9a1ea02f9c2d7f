"""Where the FE programs' compilation caches live.

Two caches share one folder: JAX's persistent cache of XLA executables, and the compiled
programs of :mod:`bristlecrawler.fe.programs` (in ``programs/``), which also skip tracing.
The stored programs are on by default, for the library as for the CLI; JAX's cache is on
where :func:`enable_compilation_cache` is called (every CLI command). Default folder
``~/.cache/bristlecrawler/jax`` (or ``$XDG_CACHE_HOME``); ``BRISTLECRAWLER_JAX_CACHE=path``
moves it, ``BRISTLECRAWLER_NO_JAX_CACHE=1`` turns both off, ``BRISTLECRAWLER_XLA_CACHE=0``
only JAX's (whose writes are not atomic: a process reading an entry that another is writing
can crash, which the stored programs' atomic writes rule out).

Together they hold at most ``BRISTLECRAWLER_CACHE_MB`` MB (default 2048): the least
recently used entries are removed when a program is stored and when JAX's cache is
enabled.

Both caches hold code that the next run executes, so the folders are made ``0700`` whatever
the umask, and a folder that another user owns, or that group or others may write, is not
used (see :mod:`bristlecrawler.fe.program_store`).
"""

from __future__ import annotations

import os
from pathlib import Path

from bristlecrawler._files import private_folder, untrusted_folder, xdg_home
from bristlecrawler.fe.cache_size import evict


def cache_folder() -> Path | None:
    """The cache folder, or None if opted out (``BRISTLECRAWLER_NO_JAX_CACHE``)."""
    if os.environ.get("BRISTLECRAWLER_NO_JAX_CACHE", "").strip() not in ("", "0"):
        return None
    path = os.environ.get("BRISTLECRAWLER_JAX_CACHE") or None  # empty: as if unset
    if path is None:
        path = xdg_home("XDG_CACHE_HOME", ".cache") / "bristlecrawler" / "jax"
    return Path(path).expanduser()


def enable_compilation_cache(path: str | os.PathLike | None = None) -> Path | None:
    """Point JAX's persistent cache at ``path`` (default :func:`cache_folder`); returns the
    folder, or None if opted out or the folder cannot be made."""
    default = cache_folder()
    if default is None or os.environ.get("BRISTLECRAWLER_XLA_CACHE", "").strip() == "0":
        return None
    import jax

    folder = Path(path).expanduser() if path is not None else default
    try:
        private_folder(folder)
    except OSError:
        return None
    reason = untrusted_folder(folder)
    if reason is not None:
        # JAX's entries are executables too: one that another user could plant is not run.
        import warnings

        from bristlecrawler.fe.program_store import CacheWarning

        warnings.warn(f"{reason}; JAX's compilation cache is off", CacheWarning, stacklevel=2)
        return None
    evict(folder)  # what earlier runs added to JAX's cache, which has no limit of its own
    jax.config.update("jax_compilation_cache_dir", str(folder))
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.5)
    return folder
