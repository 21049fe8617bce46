"""No session or issue numbers in the repository's text: history is in git, not in labels."""

from __future__ import annotations

import re
import subprocess

from realikea.files import WORKSPACE

LABEL = re.compile(r"\b(session|issue)s? [0-9]", re.IGNORECASE)
SUFFIXES = (".md", ".py", ".yaml", ".yml", ".sh", ".toml", ".cfg", ".txt")


def tracked_text_files() -> list[str]:
    out = subprocess.run(
        ["git", "ls-files"], cwd=WORKSPACE, capture_output=True, text=True, check=True
    ).stdout
    return [p for p in out.splitlines() if p.endswith(SUFFIXES)]


def test_no_text_file_labels_a_session_or_an_issue_by_number():
    found = [
        f"{path}:{number}: {line.strip()}"
        for path in tracked_text_files()
        if (WORKSPACE / path).is_file()
        for number, line in enumerate(
            (WORKSPACE / path).read_text(errors="replace").splitlines(), 1
        )
        if LABEL.search(line)
    ]
    assert not found, "\n".join(found)
