"""Numbers a hand-written README quotes from a study's data files, checked against them.

A quote is a markdown link whose text is the number and whose title is its key in the file:

    the pool ran at [0.82](bench_pool_figures.json "at_32.pool_over_limit") of the physics limit

The file (`.json`, or `.csv` read as a list of rows) is relative to the markdown file. A key is a
dotted path; on a list, a segment `field=value` picks the one item whose `field` is `value`
(`rows.envs=32.pool`), and `a=1&b=x` the one item matching both (values without dots). The
quoted text matches when it is the value written with as many decimals as the text shows; a
trailing `%` quotes a fraction as a percentage, and a leading `+`, a Unicode minus and thousands
separators are allowed. A rate with its interval, `0.90 [0.79, 0.96]`, quotes a list of three
numbers, each written as its own part shows.
"""

from __future__ import annotations

import csv
import json
import re
from dataclasses import dataclass
from functools import cache
from pathlib import Path

QUOTE = re.compile(r'\[((?:[^\[\]\n]|\[[^\[\]\n]*\])+)\]\(([^)\s]+\.(?:json|csv)) "([^"\n]+)"\)')
CODE_SPAN = re.compile(r"`[^`]*`")
INTERVAL = re.compile(r"(\S+) \[(\S+), (\S+)\]")
NUMBER = re.compile(r"([+\-−]?)(\d[\d,]*)(?:\.(\d+))?\s?(%?)")


@dataclass(frozen=True)
class Quote:
    """One quoted number: where it stands, what it says, and where its value is."""

    markdown: Path
    line: int
    text: str
    data: Path
    key: str

    def __str__(self) -> str:
        return f'{self.markdown}:{self.line}: [{self.text}]({self.data.name} "{self.key}")'


def quotes(markdown: Path) -> list[Quote]:
    """The quotes in one markdown file, in order (none in code spans or code blocks)."""
    found, fenced = [], False
    for number, line in enumerate(Path(markdown).read_text().splitlines(), 1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
        if fenced or line.startswith("    "):
            continue
        for text, data, key in QUOTE.findall(CODE_SPAN.sub("", line)):
            found.append(Quote(Path(markdown), number, text, Path(markdown).parent / data, key))
    return found


@cache
def _load(path: Path):
    if path.suffix == ".json":
        return json.loads(path.read_text())
    with path.open(newline="") as f:
        return list(csv.DictReader(f))


def lookup(data, key: str):
    """The value at a dotted `key` in loaded JSON or CSV rows (see the module docstring)."""
    value = data
    for segment in key.split("."):
        if isinstance(value, list) and "=" in segment:
            wanted = [condition.split("=", 1) for condition in segment.split("&")]
            matches = [i for i in value if all(str(i.get(f)) == v for f, v in wanted)]
            if len(matches) != 1:
                raise KeyError(f"{len(matches)} items with {segment}")
            value = matches[0]
        elif isinstance(value, dict) and segment in value:
            value = value[segment]
        elif isinstance(value, list) and segment.isdigit() and int(segment) < len(value):
            value = value[int(segment)]
        else:
            raise KeyError(f"no {segment!r}")
    return value


def written(value: float, text: str) -> str | None:
    """`value` written the way `text` writes its number (decimals, separators, sign, %), or
    None if `text` is not a number."""
    match = NUMBER.fullmatch(text.strip())
    if match is None:
        return None
    sign, whole, decimals, percent = match.groups()
    shown = float(value) * (100 if percent else 1)
    separator = "," if "," in whole else ""
    body = f"{abs(shown):{separator}.{len(decimals or '')}f}"
    negative = shown < 0 and float(body.replace(",", "")) != 0  # no "-0.00"
    prefix = ("−" if sign == "−" else "-") if negative else ("+" if sign == "+" else "")
    return prefix + body + percent


def mismatch(quote: Quote) -> str | None:
    """Why `quote` does not match its data, or None if it does."""
    if not quote.data.is_file():
        return f"{quote}: no file {quote.data}"
    try:
        value = lookup(_load(quote.data), quote.key)
    except (KeyError, AttributeError) as error:
        return f"{quote}: key not found ({error})"
    interval = INTERVAL.fullmatch(quote.text.strip())
    try:
        if interval and isinstance(value, list) and len(value) == 3:
            parts = [written(float(v), t) for v, t in zip(value, interval.groups(), strict=True)]
            expected = None if None in parts else f"{parts[0]} [{parts[1]}, {parts[2]}]"
        else:
            expected = written(float(value), quote.text)
    except (TypeError, ValueError):
        return f"{quote}: the value {value!r} is not a number"
    if expected is None:
        return f"{quote}: the quoted text is not a number"
    normal = quote.text.strip().replace(" %", "%")
    return None if expected == normal else f"{quote}: the data say {expected}"


def check(markdown_files) -> list[str]:
    """Every mismatch of every quote in `markdown_files`."""
    return [m for f in markdown_files for q in quotes(f) if (m := mismatch(q)) is not None]
