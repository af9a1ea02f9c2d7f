"""What a long command says before it starts: where it writes and how long it expects to
take, from the costs measured on this machine (:mod:`bristlecrawler.io.costs`), and the
line that announces the FE programs' compilation.

Where nothing was measured here yet, the estimate says so and quotes what was measured on
the reference machine instead (stated with it), never a guess.
"""

from __future__ import annotations

import os
from typing import Any

from bristlecrawler.io.costs import digest, duration, record, recorded

#: Compiling the paper crawler's FE programs on an empty cache, measured on an idle
#: 2-core machine (63-71 s) and on one shared by four users (about 7 min).
FIRST_COMPILE = (
    "about 70 s for the paper's crawler on an idle 2-core machine, minutes on a busy one"
)


def _cache_off() -> bool:
    return os.environ.get("BRISTLECRAWLER_NO_JAX_CACHE", "").strip() not in ("", "0")


def compile_key(spec, what: str = "crawler") -> str:
    """Equal for runs that compile the same programs (``what``: ``crawler`` or ``drag``,
    the model built from ``spec``) into the same cache. The stored programs' environment
    (the package's source, jax, the XLA flags) is part of it: after an upgrade the cache
    holds none of them, and the note must not promise a load."""
    from bristlecrawler.crawler.structure import structure_key
    from bristlecrawler.fe.programs import environment

    cache = os.environ.get("BRISTLECRAWLER_JAX_CACHE", "")
    # The drag rig drives its carriage, not the body: the stroke is not in its programs.
    leave_out = ("stroke form",) if what == "drag" else ()
    return digest([what, structure_key(spec, leave_out), cache, environment()])


#: How each kind of model is named in the lines below.
_THING = {"crawler": "crawler", "drag": "drag rig"}


def _reference(spec, what: str) -> str:
    """How long compiling ``what``'s programs takes: as measured here for this structure,
    else the reference machine's figure where there is one."""
    before = recorded("compile", compile_key(spec, what))
    if before is not None:
        return f"compiling took {duration(before.seconds)} here the last time"
    if what == "crawler":
        return f"compiling takes {FIRST_COMPILE}"
    return "no compile of them measured here yet"


def compile_note(spec, what: str = "crawler") -> str:
    """The line that announces the preparation of ``spec``'s FE programs. Whether they
    will be compiled or loaded is not known until they are (a design's values can change
    the arrays its programs are built for), so it promises neither; :class:`Preparation`
    says afterwards which it was."""
    thing = _THING.get(what, what)
    if _cache_off():
        return (
            f"compiling the {thing}'s FE programs (the compilation cache is off: every run "
            f"compiles); {_reference(spec, what)}"
        )
    return (
        f"preparing the {thing}'s FE programs: loaded from the compilation cache where an "
        f"earlier run stored them, else compiled ({_reference(spec, what)})"
    )


class Preparation:
    """The preparation of ``spec``'s FE programs in a run: ``note()`` the line before it,
    ``outcome(seconds)`` the line after it (compiled, loaded, or ready in this process
    already), ``finish(stats)`` keeps a compile's time for the next estimate (a load's
    seconds would make a false one)."""

    def __init__(self, spec, what: str = "crawler") -> None:
        from bristlecrawler.fe.programs import counts

        self.spec, self.what = spec, what
        self.before = counts()

    def _done(self) -> tuple[int, int]:
        from bristlecrawler.fe.programs import counts

        now = counts()
        return (
            now["compiled"] - self.before["compiled"],
            now["loaded"] - self.before["loaded"],
        )

    def note(self) -> str:
        return compile_note(self.spec, self.what)

    def compiled(self) -> bool:
        return _cache_off() or self._done()[0] > 0

    def outcome(self, seconds: float) -> str:
        thing = _THING.get(self.what, self.what)
        compiled, loaded = self._done()
        took = f"{seconds:.0f} s"
        if _cache_off() or (compiled and not loaded):
            return f"the {thing}'s FE programs: compiled in {took}"
        if compiled:
            return (
                f"the {thing}'s FE programs: {compiled} compiled and {loaded} loaded from the "
                f"compilation cache in {took}"
            )
        if loaded:
            return f"the {thing}'s FE programs: loaded from the compilation cache in {took}"
        return f"the {thing}'s FE programs: ready in {took} (this process had them already)"

    def stage_note(self):
        """The compiling stage's note for :func:`bristlecrawler.viz.progress.sim_progress`."""
        from bristlecrawler.viz.progress import StageNote

        return StageNote(self.note, self.outcome)

    def finish(self, stats: dict) -> None:
        if self.compiled():
            record_compile(self.spec, stats.get("compile_time_s", float("nan")), self.what)
        else:
            _COMPILED.add(compile_key(self.spec, self.what))


def record_compile(spec, seconds: float, what: str = "crawler") -> None:
    record("compile", compile_key(spec, what), seconds)
    _COMPILED.add(compile_key(spec, what))


#: Programs this process compiled already (JAX keeps them: a later run starts at once).
_COMPILED: set[str] = set()


def compile_announcer(spec, say, what: str = "crawler"):
    """A progress callback's helper for a run inside a longer job: ``seen(stage)`` says
    the preparation's note with ``say(text)`` when the preparation of programs this process
    does not hold yet starts; ``done(stats)`` says what it turned out to be (compiled or
    loaded) and how long it took, and keeps a compile's time."""
    prep = Preparation(spec, what)

    class _Announcer:
        said = False

        def seen(self, stage: str) -> None:
            if stage == "compiling" and not self.said:
                self.said = True
                if compile_key(spec, what) not in _COMPILED:
                    say(prep.note())
                else:
                    self.said = None  # prepared in this process: nothing to announce

        def done(self, stats: dict) -> None:
            seconds = stats.get("compile_time_s", float("nan"))
            if self.said and seconds == seconds:
                say(prep.outcome(seconds))
            prep.finish(stats)

    return _Announcer()


def scenario_key(kind: str, config: dict[str, Any]) -> str:
    """A run's key: its command and its configuration without the outputs it writes."""
    relevant = {k: v for k, v in config.items() if k not in ("name", "description", "output")}
    return digest([kind, relevant])


def expected(kind: str, key: str, otherwise: str) -> str:
    """``expected about 3 min once the FE programs are ready (its last run here, DATE)``,
    or ``otherwise``: runs are recorded without their compile time, which the compile
    line states on its own."""
    before = recorded(kind, key)
    if before is None:
        return otherwise
    when = before.utc[:10]
    return (
        f"expected {duration(before.seconds)} once the FE programs are ready "
        f"(its last run here, {when})"
    )


def unmeasured(what: str, estimate: str | None) -> str:
    """What the first line says where no earlier ``what`` was measured here: the a-priori
    ``estimate`` (from the reference machine's costs), if there is one."""
    if estimate is None:
        return f"no earlier {what} here to estimate its time from"
    return f"no earlier {what} here; from the reference machine's costs, {estimate}"


def run_seconds(wall_s: float, stats: dict) -> float:
    """A run's wall time without its compilation (unknown compile time: all of it)."""
    compile_s = stats.get("compile_time_s", float("nan"))
    return wall_s - compile_s if compile_s == compile_s else wall_s
