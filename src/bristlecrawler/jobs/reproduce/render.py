"""The report as Markdown (``report.md``, figures linked beside it) and as one
self-contained HTML file (``report.html``, figures embedded as data URIs, so it opens from
anywhere, mailed or moved)."""

from __future__ import annotations

import base64
import html
import re
from dataclasses import dataclass
from pathlib import Path

from bristlecrawler.jobs.reproduce.parts import Part, PartResult
from bristlecrawler.jobs.reproduce.table import Row

#: Animations larger than this are linked beside the report instead of embedded, bytes.
EMBED_LIMIT = 12_000_000


@dataclass(frozen=True)
class Report:
    """Everything the report shows."""

    title: str
    header: tuple[str, ...]
    rows: tuple[Row, ...]
    sections: tuple[tuple[Part, PartResult], ...]


def _fmt(x: float | None, unit: str) -> str:
    if x is None:
        return ""
    digits = 3 if unit in ("N", "N/mm") or abs(x) < 10 else 2
    return f"{x:.{digits}f}"


def _difference(x: float | None, unit: str) -> str:
    """Ours minus the paper's, signed, with its unit: ``+1.234 mm``."""
    return "" if x is None else f"{'+' if x >= 0 else '-'}{_fmt(abs(x), unit)} {unit}"


def _cells(r: Row) -> list[str]:
    ours = r.ours_text if r.ours_text and r.ours is None else _fmt(r.ours, r.unit)
    if r.ours is not None and r.ours_text:
        ours = r.ours_text
    return [
        f"{r.quantity} ({r.unit})",
        r.paper_text,
        ours,
        _difference(r.difference, r.unit),
        r.verdict,
        r.source,
    ]


HEAD = ["quantity", "paper", "bristlecrawler", "ours - paper", "verdict", "ours from"]


def _why(r: Row) -> str:
    """The row's reason, and the documentation section that explains it (by name: the
    report is read away from the docs)."""
    return r.reason + (f" (docs: {r.docs})" if r.docs else "")


def took(wall_s: float) -> str:
    """``This part took 655 s (11 min).``"""
    minutes = f" ({wall_s / 60:.0f} min)" if wall_s >= 90 else ""
    return f"This part took {wall_s:.0f} s{minutes}."


def markdown(rep: Report) -> str:
    out = [f"# {rep.title}", "", *rep.header, "", "## Paper versus bristlecrawler", ""]
    out += ["| " + " | ".join([*HEAD, "why"]) + " |", "|" + "---|" * (len(HEAD) + 1)]
    for r in rep.rows:
        out.append("| " + " | ".join(c.replace("|", "\\|") for c in [*_cells(r), _why(r)]) + " |")
    for part, res in rep.sections:
        out += ["", f"## {part.title}", ""]
        if not res.ok:
            out += [f"**This part failed**: {res.error}", ""]
        out += list(res.lines)
        for fig in res.figures:
            out += ["", f"![{fig.caption}]({fig.path})", "", f"*{fig.caption}*"]
        out += ["", f"<small>{took(res.wall_s)}</small>"]
    return "\n".join(out) + "\n"


_INLINE = (
    (re.compile(r"\*\*(.+?)\*\*"), r"<strong>\1</strong>"),
    (re.compile(r"(?<![\w*])\*([^*\s][^*]*?)\*(?![\w*])"), r"<em>\1</em>"),
    (re.compile(r"`(.+?)`"), r"<code>\1</code>"),
    (re.compile(r"\[([^\]]+)\]\(([^)\s]+)\)"), r'<a href="\2">\1</a>'),
)


def _inline(text: str) -> str:
    """The Markdown the parts write (bold, code, links) as HTML, the rest escaped."""
    out = html.escape(text, quote=False)
    for pattern, repl in _INLINE:
        out = pattern.sub(repl, out)
    return out


def _blocks(lines: tuple[str, ...] | list[str]) -> str:
    """Paragraphs and bullet lists of Markdown lines as HTML."""
    out, items, para = [], [], []

    def flush():
        if para:
            out.append(f"<p>{_inline(' '.join(para))}</p>")
            para.clear()
        if items:
            out.append("<ul>" + "".join(f"<li>{_inline(i)}</li>" for i in items) + "</ul>")
            items.clear()

    for line in lines:
        if line.startswith("* "):
            if para:
                flush()
            items.append(line[2:])
        elif not line.strip():
            flush()
        else:
            if items:
                flush()
            para.append(line)
    flush()
    return "\n".join(out)


def _data_uri(path: Path) -> str:
    kind = {".png": "image/png", ".gif": "image/gif"}[path.suffix.lower()]
    return f"data:{kind};base64," + base64.b64encode(path.read_bytes()).decode("ascii")


def _figure(folder: Path, path: str, caption: str) -> str:
    file = folder / path
    if not file.is_file():
        return f"<p><em>missing figure: {html.escape(path)}</em></p>"
    cap = html.escape(caption)
    if file.stat().st_size > EMBED_LIMIT:
        return f'<p><a href="{html.escape(path)}">{cap}</a> (too large to embed)</p>'
    return (
        f'<figure><img src="{_data_uri(file)}" alt="{cap}"><figcaption>{cap}</figcaption></figure>'
    )


STYLE = """
body { font-family: system-ui, sans-serif; max-width: 1100px; margin: 2em auto; padding: 0 1em;
       color: #222; line-height: 1.45; }
table { border-collapse: collapse; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 0.3em 0.5em; vertical-align: top; }
th { background: #eef5f4; }
td.agrees { color: #1a7f37; } td.differs { color: #b35900; font-weight: bold; }
td.inconclusive { color: #6a4fb3; font-weight: bold; }
figure { margin: 1em 0; } img { max-width: min(100%, 860px); border: 1px solid #eee; }
figcaption { font-size: 0.85em; color: #555; }
.failed { background: #fde8e8; border-left: 4px solid #c00; padding: 0.5em 1em; }
code { background: #f4f4f4; padding: 0 0.2em; }
"""


def to_html(rep: Report, folder: Path) -> str:
    """The report as one HTML page; figures read from ``folder`` and embedded."""
    out = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>{html.escape(rep.title)}</title><style>{STYLE}</style></head><body>",
        f"<h1>{html.escape(rep.title)}</h1>",
        _blocks(rep.header),
        "<h2>Paper versus bristlecrawler</h2>",
        "<table><thead><tr>",
        "".join(f"<th>{html.escape(h)}</th>" for h in [*HEAD, "why"]),
        "</tr></thead><tbody>",
    ]
    for r in rep.rows:
        cells = _cells(r)
        verdict = cells[4]
        tds = [f"<td>{html.escape(c)}</td>" for c in cells]
        tds[4] = f'<td class="{verdict}">{html.escape(verdict)}</td>'
        why = _inline(_why(r))
        out.append(f'<tr id="row-{r.key}">' + "".join(tds) + f"<td>{why}</td></tr>")
    out.append("</tbody></table>")
    for part, res in rep.sections:
        out.append(f'<h2 id="{part.name}">{html.escape(part.title)}</h2>')
        if not res.ok:
            out.append(
                f'<p class="failed"><strong>This part failed</strong>: {html.escape(res.error)}</p>'
            )
        out.append(_blocks(res.lines))
        out += [_figure(folder, f.path, f.caption) for f in res.figures]
        out.append(f"<p><small>{html.escape(took(res.wall_s))}</small></p>")
    out.append("</body></html>")
    return "\n".join(out) + "\n"
