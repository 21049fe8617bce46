"""Every study script answers `--help`: it prints its docstring's first paragraph and exits 0,
so a script that ignores its command line (and runs its whole job on any flag) fails."""

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
    first_paragraph = " ".join(module.__doc__.split("\n\n")[0].split())
    assert first_paragraph in " ".join(capsys.readouterr().out.split())
