"""Every study script answers `--help` with its docstring's first paragraph and does no work:
its `main` parses the command line before it reads or writes anything."""

from __future__ import annotations

import inspect
import sys

import pytest

from realikea.files import WORKSPACE

SCRIPTS = sorted(
    str(path.relative_to(WORKSPACE))
    for path in WORKSPACE.glob("experiments/*/*.py")
    if "\ndef main(" in path.read_text()
)


@pytest.mark.parametrize("script", SCRIPTS)
def test_help_prints_the_docstring_and_does_no_work(script, load_script, capsys, monkeypatch):
    module = load_script(script)
    monkeypatch.setattr(sys, "argv", [script, "--help"])
    takes_argv = bool(inspect.signature(module.main).parameters)
    with pytest.raises(SystemExit) as stop:
        module.main(["--help"]) if takes_argv else module.main()
    assert stop.value.code == 0
    first_line = module.__doc__.strip().splitlines()[0].split()[0]
    assert first_line in capsys.readouterr().out
