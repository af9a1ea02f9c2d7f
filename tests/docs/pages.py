"""Code blocks and inline code of the project's Markdown pages."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
_FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.S | re.M)


def blocks(language: str) -> list[tuple[str, int, str]]:
    """(page, index, code) of every fenced block in ``language`` on every page."""
    out = []
    for page in PAGES:
        found = [code for lang, code in _FENCE.findall(page.read_text()) if lang == language]
        out += [(str(page.relative_to(ROOT)), i, code) for i, code in enumerate(found)]
    return out


def shell_commands(code: str) -> list[str]:
    """The commands of a shell block: continuation lines joined, comments and heredoc
    bodies dropped, ``a && b`` split."""
    lines, heredoc = [], None
    for raw in code.replace("\\\n", " ").splitlines():
        if heredoc is not None:
            if raw.strip() == heredoc:
                heredoc = None
            continue
        m = re.search(r"<<\s*'?(\w+)'?", raw)
        if m:
            heredoc = m.group(1)
        line = re.sub(r"(^|\s)#.*$", "", raw).strip()
        if line:
            lines += [part.strip() for part in line.split("&&")]
    return lines
