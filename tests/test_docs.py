"""The docs stay true: every command, flag, override, path and link they name exists.

Docs: README.md, DATASET.md, docs/*.md, experiments/*/README.md, realikea/catalog/README.md.
Every command's script, module or `realikea` sub-command exists and knows the flags given (a
code block's `realikea` line also parses), its Hydra overrides compose, the repo paths it reads
exist. Every link and backticked repo path exists and is not git-ignored, every `#anchor` is a
heading of its page, every `group=a|b` in prose names config files, every `file.py: NAME` or
`tests/x.py::test` a definition in that file.

Cheap, so also run: `--help` (in-process: the scripts' imports take 0.5-14 s in a subprocess),
`python -m realikea.eval.stats` (arithmetic), `. FILE`, a `python3 -c` snippet whose output its
block shows (compared), and the README's quick start: its one-configuration build and its
training cut to 2 tiny iterations (both into tmp_path), its evaluation's set-up (the checkpoint
loads; no episode). Everything else (set-up, full builds, training, evaluation, benchmarks,
shell scripts, the MuJoCo viewer, which needs a display) is only checked as above.

A command is a line of a shell code block (fenced bash/sh/unlabelled, or indented) or an inline
code span (which may leave out required arguments) that starts with python/python3/realikea/bash
/`.`; a block's other lines after a command are its output. Placeholders are skipped: `<...>`,
`...`, a whole `{a,b}` token, an upper-case word as a token, path segment or value (`DIR`,
`RUN/model_999.pt`, `K/N`) and an override whose value is one; `[...]` marks optional arguments,
checked like the rest; `a|b` in an override is either; outputs (`--out`, `video_path=`, ...) need
not exist.
"""

from __future__ import annotations

import contextlib
import functools
import importlib.util
import io
import logging
import re
import runpy
import shlex
import subprocess
import sys
import warnings
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from hydra._internal.utils import get_args_parser
from hydra.core.config_store import ConfigStore
from hydra.core.object_type import ObjectType
from omegaconf import OmegaConf

from realikea.cli import build_parser, main
from realikea.config import load_config
from realikea.eval.commands import with_default_command
from realikea.eval.setup import eval_setup
from realikea.files import CONF_DIR, WORKSPACE
from realikea.rewards import store_configs

DOCS = ["README.md", "DATASET.md", "realikea/catalog/README.md"] + [
    str(p.relative_to(WORKSPACE))
    for pattern in ("docs/*.md", "experiments/*/README.md")
    for p in sorted(WORKSPACE.glob(pattern))
]
PROGRAMS = {"python", "python3", "realikea", "bash", "."}
SHELL_FENCES = {"", "bash", "sh", "shell", "console"}
REPO_ROOTS = ("realikea/", "experiments/", "tests/", "docs/", ".ci/")
ROOT_FILES = {"README.md", "DATASET.md", "train.py", "setup.sh", "env.sh", "pyproject.toml"}
GENERATED = ("outputs/", ".cache/", "assets/imported/", ".venv/")
HYDRA_ENTRIES = {("script", "train.py"), ("realikea", "train")}
OUTPUTS = {"--out", "hydra.run.dir", "record", "policy.record", "video_path"}  # written, not read
# the quick start's training cut to two tiny iterations (as tests/test_train_eval.py's SMALL) on
# the configuration its build made
TINY = ["agent.max_iterations=2", "agent.num_steps_per_env=8", "env.num_envs=2"]
TINY += ["env.num_workers=0", "task.episode_seconds=1.5", "dr=fixed"]
TINY += ["asset.part=tp_round_bar_128", "asset.base=drawer_w60_h20"]


# --- reading the docs ---------------------------------------------------------------------


@dataclass
class Command:
    """One command a doc gives: in a code block (whole, with the output lines the block shows
    after it) or inline."""

    doc: str
    line: int
    argv: tuple[str, ...]
    in_block: bool
    output: list[str] = field(default_factory=list)

    def __str__(self) -> str:
        return f"{self.doc}:{self.line} {' '.join(self.argv)[:70]}"


@dataclass(frozen=True)
class Mention:
    """A repo path (or a config group option, a definition) a doc names at a line."""

    doc: str
    line: int
    name: str

    def __str__(self) -> str:
        return f"{self.doc}:{self.line} {self.name}"


@functools.cache
def split_doc(doc: str) -> tuple[list[tuple[int, list[str]]], list[str]]:
    """A doc's shell code blocks (first line number, lines) and its prose: its lines with code
    blanked, so line numbers stay. Fenced blocks are code; an indented block only if it holds a
    command (else it is a list item's paragraph)."""
    lines = (WORKSPACE / doc).read_text().splitlines()
    prose, blocks, fence = list(lines), [], None
    indented: list[tuple[int, list[str]]] = []
    for i, line in enumerate(lines):
        if fence is not None or line.lstrip().startswith("```"):
            prose[i] = ""
            if fence is None:
                fence = (i, line.strip().strip("`").strip() in SHELL_FENCES)
            elif line.lstrip().startswith("```"):
                if fence[1]:
                    blocks.append((fence[0] + 2, lines[fence[0] + 1 : i]))
                fence = None
        elif line.startswith("    ") and (i == 0 or not lines[i - 1].strip()):
            indented.append((i + 1, [line]))
        elif indented and indented[-1][0] + len(indented[-1][1]) == i + 1 and not line[:4].strip():
            indented[-1][1].append(line)  # the block goes on: indented or blank
    for start, block in indented:
        if any(shell_commands(text) for _, text in logical_lines(start, block)):
            blocks.append((start, block))
            prose[start - 1 : start - 1 + len(block)] = [""] * len(block)
    return sorted(blocks), prose


def clean(token: str) -> str:
    """A token without the `[` `]` that mark it optional (`[--id`, `NAME]`, `[video=true]`)."""
    token = token.removeprefix("[")
    return token[:-1] if token.endswith("]") and "[" not in token else token


def shell_commands(text: str) -> list[tuple[str, ...]]:
    """The commands of a shell line (split at `&&`, `;`, `|`; leading VAR=value dropped) that
    start with a known program; none unless the line's first one does."""
    try:
        tokens = shlex.split(re.sub(r"<[\w .-]+>", "<_>", text), comments=True)
    except ValueError:  # prose in backticks with an apostrophe
        return []
    commands, current = [], []
    for token in [*tokens, "&&"]:
        if token in {"&&", "||", ";", "|"}:
            while current and re.fullmatch(r"[A-Z_][A-Z0-9_]*=\S*", current[0]):
                current.pop(0)
            if len(current) >= 2 and current[0] in PROGRAMS:
                commands.append(tuple(clean(t) for t in current))
            elif not commands:
                return []
            current = []
        else:
            current.append(token)
    return commands


def logical_lines(start: int, lines: list[str]):
    """(line number, text) of a block's lines with `\\` continuations joined."""
    pending, first = "", start
    for number, line in enumerate(lines, start):
        if not pending:
            first = number
        if line.rstrip().endswith("\\"):
            pending += line.rstrip()[:-1] + " "
            continue
        yield first, pending + line
        pending = ""


def inline_spans(doc: str):
    """(line number, text) of every inline code span of a doc's prose, line breaks as spaces."""
    text = "\n".join(split_doc(doc)[1])
    for match in re.finditer(r"`([^`]+)`", text):
        yield text.count("\n", 0, match.start()) + 1, " ".join(match.group(1).split())


@functools.cache
def commands() -> list[Command]:
    """Every command of every doc: code-block lines (with their output) and inline spans."""
    found = []
    for doc in DOCS:
        blocks, _ = split_doc(doc)
        for start, lines in blocks:
            block = []
            for number, text in logical_lines(start, lines):
                argvs = shell_commands(text)
                block += [Command(doc, number, argv, True) for argv in argvs]
                if not argvs and block and text.strip() and not text.lstrip().startswith("#"):
                    block[-1].output.append(text.strip())
            found += block
        for number, text in inline_spans(doc):
            found += [Command(doc, number, argv, False) for argv in shell_commands(text)]
    return found


# --- what a command runs --------------------------------------------------------------------


@dataclass(frozen=True)
class Target:
    """What a command runs: a `script` or `shell` file, a `module`, a `snippet` of code or a
    `realikea` sub-command ("eval run"), and the arguments given to it."""

    kind: str
    name: str
    args: tuple[str, ...]


def target(argv: tuple[str, ...]) -> Target:
    """What a command line runs (`realikea eval OVERRIDES` is `eval run`, as the CLI has it)."""
    head, *rest = argv
    if head == "realikea":
        group, *rest = rest or [""]
        if group == "eval":
            rest = with_default_command(rest)
        if group != "train" and rest and re.fullmatch(r"[a-z]+", rest[0]):
            group, *rest = [f"{group} {rest[0]}", *rest[1:]]
        return Target("realikea", group, tuple(rest))
    if head in {"python", "python3"} and rest[0] in {"-m", "-c"}:
        return Target({"-m": "module", "-c": "snippet"}[rest[0]], rest[1], tuple(rest[2:]))
    return Target("script" if head.startswith("python") else "shell", rest[0], tuple(rest[1:]))


def is_placeholder(token: str) -> bool:
    """`<...>`, `...`, a whole `{a,b}` token or an upper-case word as a path segment or value."""
    if "<" in token or "..." in token or re.fullmatch(r"\{.*\}", token):
        return True
    return any(re.fullmatch(r"[A-Z][A-Z0-9_]*", part) for part in re.split(r"[/=,:]", token))


def flags(args: tuple[str, ...]) -> list[str]:
    """The options among `args` (up to a bare `--`), without their `=value`."""
    found = []
    for token in args:
        if token == "--":
            break
        if re.match(r"--?[a-zA-Z]", token):
            found.append(token.split("=", 1)[0])
    return found


def overrides(target: Target) -> list[str]:
    """The Hydra overrides a command gives (placeholders dropped): `key=value` tokens of train.py,
    `realikea train` and the `realikea` sub-commands."""
    if target.kind != "realikea" and (target.kind, target.name) not in HYDRA_ENTRIES:
        return []
    given = [t for t in target.args if "=" in t and not t.startswith("-")]
    return [t for t in given if not is_placeholder(t)]


def config_name(target: Target) -> str:
    return "eval" if target.name.startswith("eval") else "config"


def compositions(target: Target) -> list[list[str]]:
    """The override lists to compose: the first value of each key, then each other option of a
    config group given alternatives (`a|b`, or `a,b` under `-m`)."""
    given = [o.split("=", 1) for o in overrides(target)]
    either = "[,|]" if "-m" in target.args or "--multirun" in target.args else "[|]"
    values = [re.split(either, value) for _, value in given]
    first = [f"{key}={v[0]}" for (key, _), v in zip(given, values, strict=True)]
    return [first] + [
        [*first[:i], f"{key}={value}", *first[i + 1 :]]
        for i, ((key, _), v) in enumerate(zip(given, values, strict=True))
        if (CONF_DIR / key.lstrip("+")).is_dir()
        for value in v[1:]
    ]


def source(target: Target) -> Path | None:
    """The Python file a script or a module command runs."""
    if target.kind == "script":
        return WORKSPACE / target.name
    spec = importlib.util.find_spec(target.name) if target.kind == "module" else None
    return Path(spec.origin) if spec and spec.origin else None


def uses_argparse(target: Target) -> bool:
    path = source(target)
    return path is not None and path.is_file() and "argparse" in path.read_text()


def start(target: Target) -> int:
    """Run a script or module as `__main__`, or `realikea`'s main, with the target's arguments."""
    if target.kind == "realikea":
        return main([*target.name.split(), *target.args])
    sys.argv = [target.name, *target.args]
    if target.kind == "module":
        runpy.run_module(target.name, run_name="__main__", alter_sys=True)
    else:  # as `PYTHONPATH=. python SCRIPT` sees it
        sys.path[:0] = [str((WORKSPACE / target.name).parent), str(WORKSPACE)]
        runpy.run_path(str(WORKSPACE / target.name), run_name="__main__")
    return 0


@functools.cache
def run_in_process(target: Target) -> tuple[int, str]:
    """A script's, module's or `realikea` command's exit code and output, run in this process:
    their imports are shared (in a subprocess each takes 0.5-14 s)."""
    out, argv, path = io.StringIO(), sys.argv, list(sys.path)
    root = logging.getLogger()
    level, handlers = root.level, list(root.handlers)
    quiet = contextlib.redirect_stdout(out), contextlib.redirect_stderr(out)
    try:
        with quiet[0], quiet[1], warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # runpy: a module imported before
            code = start(target)
    except SystemExit as stop:
        code = stop.code if isinstance(stop.code, int) else int(stop.code is not None)
    finally:  # no trace left (Hydra's --help, for one, sets up the root logger)
        sys.argv, sys.path[:] = argv, path
        root.setLevel(level)
        root.handlers[:] = handlers
    return code, out.getvalue()


def help_of(target: Target) -> tuple[int, str]:
    """The exit code and text of the target's `--help` (Hydra's flags for a Hydra entry)."""
    if (target.kind, target.name) in HYDRA_ENTRIES:
        parser = get_args_parser()  # Hydra's own; its format_help fails on a lazy help string
        return 0, " ".join(parser._option_string_actions)
    return run_in_process(Target(target.kind, target.name, ("--help",)))


def is_cheap(command: Command) -> bool:
    """Whether the test runs the command itself (the module docstring's rule)."""
    t = target(command.argv)
    if t.kind == "snippet":
        return bool(command.output)
    if t.kind == "shell":
        return command.argv[0] == "." and not t.name.removeprefix("./").startswith(GENERATED)
    if t.kind == "module" and not t.name.startswith("realikea"):
        return False
    arithmetic = t.name == "realikea.eval.stats" and not any(map(is_placeholder, t.args))
    return "--help" in t.args or arithmetic


# --- repo paths, links and anchors --------------------------------------------------------


def repo_path(token: str) -> str | None:
    """The repo path a token names (workspace-relative), if it names one that is not generated."""
    token = token.strip("()[],;:'\"").rstrip(".").removeprefix("./").split("::")[0]
    if is_placeholder(token) or token.startswith(GENERATED):
        return None
    return token if token.startswith(REPO_ROOTS) or token in ROOT_FILES else None


def inputs(args) -> list[str]:
    """A command's arguments and the values of its `key=value` and `--flag=value`, less the
    outputs it writes (`--out DIR`, `video_path=STEM`, ...: they need not exist)."""
    found, output = [], False
    for token in args:
        key, _, value = token.partition("=")
        if not output and key not in OUTPUTS:
            found.append(value or key)
        output = token in OUTPUTS
    return found


def blank(match: re.Match) -> str:
    return re.sub(r"[^\n]", " ", match.group())


@functools.cache
def links() -> list[Mention]:
    """Every relative Markdown link and image outside code (its target as the name)."""
    found = []
    for doc in DOCS:
        text = re.sub(r"`[^`]*`", blank, "\n".join(split_doc(doc)[1]))
        for match in re.finditer(r"!?\[[^\]]*\]\(([^)\s]+)\)", text):
            if not re.match(r"[a-z]+:", match.group(1)):
                found.append(Mention(doc, text.count("\n", 0, match.start()) + 1, match.group(1)))
    return found


def linked_path(doc: str, link: str) -> str:
    """A link's file, workspace-relative ("" for an anchor in the same doc)."""
    file = link.split("#", 1)[0]
    if not file:
        return ""
    resolved = ((WORKSPACE / doc).parent / file).resolve()
    return str(resolved.relative_to(WORKSPACE.resolve())) + ("/" if file.endswith("/") else "")


@functools.cache
def path_mentions() -> list[Mention]:
    """Every repo path named in a command, an inline code span or a link, once per line."""
    found = {}
    for command in commands():
        if target(command.argv).kind == "snippet":  # its paths are checked by running it
            continue
        for token in inputs(command.argv[1:]):
            found.setdefault(Mention(command.doc, command.line, repo_path(token)), None)
    for doc in DOCS:
        for number, text in inline_spans(doc):
            if shell_commands(text):  # a command: done above
                continue
            for token in inputs(text.split()):
                found.setdefault(Mention(doc, number, repo_path(token)), None)
    for link in links():
        if not link.name.startswith("#"):
            found.setdefault(Mention(link.doc, link.line, linked_path(link.doc, link.name)), None)
    return [m for m in found if m.name]


def expand_braces(pattern: str) -> list[str]:
    """Bash's `a{,_b}c` -> `ac`, `a_bc` (one level)."""
    match = re.search(r"\{([^{}]*)\}", pattern)
    if not match:
        return [pattern]
    head, tail = pattern[: match.start()], pattern[match.end() :]
    return [p for alt in match.group(1).split(",") for p in expand_braces(head + alt + tail)]


def matches(path: str) -> list[Path]:
    """The files a repo path names: itself, or what its glob and brace pattern match."""
    return [p for pattern in expand_braces(path) for p in WORKSPACE.glob(pattern.rstrip("/"))]


@functools.cache
def git_ignored() -> tuple[str, ...]:
    """Ignored paths of the checkout (folders end with /); none outside a git checkout."""
    out = subprocess.run(
        ["git", "ls-files", "--others", "--ignored", "--exclude-standard", "--directory"],
        cwd=WORKSPACE,
        capture_output=True,
        text=True,
    )
    return tuple(out.stdout.split()) if out.returncode == 0 else ()


def slug(heading: str) -> str:
    """GitHub's anchor for a heading: lower case, punctuation but - and _ dropped, spaces to -."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


@functools.cache
def anchors(doc: str) -> set[str]:
    """The anchors of a Markdown file's headings (a repeated heading gets -1, -2, ...)."""
    found, seen = set(), Counter()
    for line in split_doc(doc)[1]:
        heading = re.match(r"#{1,6}\s+(.*?)\s*#*$", line)
        if heading:
            base = slug(heading.group(1))
            found.add(f"{base}-{seen[base]}" if seen[base] else base)
            seen[base] += 1
    return found


# --- config groups and definitions named in prose -------------------------------------------


def is_config_group(name: str) -> bool:
    """Whether `name` is a Hydra config group: a folder of realikea/conf/ or a group registered
    in code (`task/reward`, from the reward variants' params)."""
    store_configs()
    return (CONF_DIR / name).is_dir() or ConfigStore.instance().get_type(name) == ObjectType.GROUP


def group_mentions() -> list[Mention]:
    """Inline `group=option[|option...]` spans whose group is a config group."""
    return [
        Mention(doc, number, text)
        for doc in DOCS
        for number, text in inline_spans(doc)
        if re.fullmatch(r"\+?[\w/]+=[\w|]+", text)
        and is_config_group(text.lstrip("+").split("=")[0])
    ]


def definition_mentions() -> list[Mention]:
    """Inline `path: NAME` and `path::NAME` spans: a name defined in a Python file (a test) or a
    key of a YAML file."""
    return [
        Mention(doc, number, text)
        for doc in DOCS
        for number, text in inline_spans(doc)
        if re.fullmatch(r"[\w/]+\.(py|yaml)(: |::)[\w.]+", text)
    ]


# --- the tests --------------------------------------------------------------------------------


def with_target(predicate):
    return [c for c in commands() if predicate(target(c.argv))]


@pytest.mark.parametrize("command", commands(), ids=str)
def test_the_program_exists(command):
    t = target(command.argv)
    if t.kind in {"script", "shell"}:
        path = t.name.removeprefix("./")
        generated = is_placeholder(path) or path.startswith(GENERATED)
        assert generated or matches(path), f"{command}: no file {t.name}"
    elif t.kind == "module":
        assert importlib.util.find_spec(t.name), f"{command}: no module {t.name}"
    elif t.kind == "realikea":
        code, text = help_of(t)
        assert code == 0, f"{command}: `realikea {t.name}` is no command:\n{text[-500:]}"


def is_ours(target: Target) -> bool:
    """A repo script, a `realikea` module or sub-command: its options are ours to check."""
    return target.kind in {"script", "realikea"} or target.name.startswith("realikea.")


@pytest.mark.parametrize("command", with_target(lambda t: is_ours(t) and flags(t.args)), ids=str)
def test_every_flag_is_one_the_program_knows(command):
    t = target(command.argv)
    hydra = (t.kind, t.name) in HYDRA_ENTRIES
    if t.kind != "realikea" and not hydra:
        assert uses_argparse(t), f"{command}: {t.name} has no argument parser for {flags(t.args)}"
    code, text = help_of(t)
    assert code == 0, text[-1000:]
    shown = {f for f in flags(t.args) if re.search(rf"(?<![\w-]){re.escape(f)}(?![\w-])", text)}
    unknown = [f for f in flags(t.args) if f not in shown]
    assert not unknown, f"{command}: {t.name} has no option {unknown}"


def is_realikea_line(command: Command) -> bool:
    """A whole `realikea` command line (a code block's), not handed to Hydra, not `--help`."""
    whole = command.in_block and "--help" not in command.argv
    return whole and command.argv[0] == "realikea" and command.argv[1:2] != ("train",)


@pytest.mark.parametrize("command", [c for c in commands() if is_realikea_line(c)], ids=str)
def test_the_realikea_command_line_parses(command):
    t = target(command.argv)
    err = io.StringIO()
    try:
        with contextlib.redirect_stderr(err):
            build_parser().parse_args([*t.name.split(), *t.args])
    except SystemExit:
        pytest.fail(f"{command}: {err.getvalue().strip().splitlines()[-1]}")


@pytest.mark.parametrize("command", with_target(overrides), ids=str)
def test_the_overrides_compose(command):
    t = target(command.argv)
    for given in compositions(t):
        load_config(given, config_name(t))  # a RealIkeaError names the bad override


def is_ignored(path: Path) -> bool:
    relative = str(path.relative_to(WORKSPACE)) + ("/" if path.is_dir() else "")
    return any(relative.startswith(i) if i.endswith("/") else relative == i for i in git_ignored())


@pytest.mark.parametrize("mention", path_mentions(), ids=str)
def test_the_repo_path_exists_in_a_clone(mention):
    found = matches(mention.name)
    assert found, f"{mention}: no such file or folder"
    assert not all(map(is_ignored, found)), f"{mention}: git-ignored, so not in a clone"


@pytest.mark.parametrize("link", [m for m in links() if "#" in m.name], ids=str)
def test_the_link_anchor_is_a_heading(link):
    page = linked_path(link.doc, link.name) or link.doc
    anchor = link.name.split("#", 1)[1]
    assert page.endswith(".md"), f"{link}: an anchor into {page}, not a Markdown page"
    assert anchor in anchors(page), f"{link}: {page} has no heading #{anchor}"


@pytest.mark.parametrize("mention", group_mentions(), ids=str)
def test_the_config_group_options_exist(mention):
    group, options = mention.name.lstrip("+").split("=")
    for option in options.split("|"):
        if not (CONF_DIR / group / f"{option}.yaml").is_file():
            load_config([f"{group}={option}"])  # e.g. a Hydra plugin's launcher


@pytest.mark.parametrize("mention", definition_mentions(), ids=str)
def test_the_named_definition_exists(mention):
    path, name = re.split(r": |::", mention.name)
    text = (WORKSPACE / path).read_text()
    if path.endswith(".yaml"):
        assert OmegaConf.select(OmegaConf.create(text), name) is not None, f"{mention}: no key"
    else:
        definition = rf"^(class |def )?{name}\b\s*[(:=]"
        assert re.search(definition, text, re.M), f"{mention}: {name} is not defined there"


@pytest.mark.parametrize("command", [c for c in commands() if is_cheap(c)], ids=str)
def test_the_cheap_command_runs(command):
    t = target(command.argv)
    if t.kind == "snippet":
        out = subprocess.run(
            [sys.executable, "-c", t.name], cwd=WORKSPACE, capture_output=True, text=True
        )
        assert out.returncode == 0, out.stderr[-1000:]
        assert out.stdout.splitlines() == command.output, f"{command}: the doc shows other output"
    elif t.kind == "shell":
        out = subprocess.run(["bash", "-c", f". {t.name}"], cwd=WORKSPACE, capture_output=True)
        assert out.returncode == 0, out.stderr
    else:
        code, text = run_in_process(t)
        assert code == 0, f"{command}:\n{text[-1000:]}"


# --- the README's quick start -------------------------------------------------------------


def quick_start(*prefix: str) -> Command:
    """The README quick start's command that starts with `prefix`."""
    prose = split_doc("README.md")[1]
    begin = next(i for i, line in enumerate(prose) if line.startswith("## Quick start")) + 1
    end = next(i for i, line in enumerate(prose) if i > begin and line.startswith("## ")) + 1
    found = [
        c
        for c in commands()
        if c.doc == "README.md" and begin < c.line < end and c.argv[: len(prefix)] == prefix
    ]
    assert len(found) == 1, f"the quick start has {len(found)} commands {' '.join(prefix)}"
    return found[0]


def replaced(argv, extra: list[str]) -> list[str]:
    """`argv` with the overrides in `extra` replacing those of the same key."""
    keys = {e.split("=")[0] for e in extra}
    return [a for a in argv if a.split("=")[0] not in keys] + extra


@pytest.fixture(scope="module")
def quick_start_library(tmp_path_factory):
    """The quick start's one-configuration build, into a temporary library."""
    library = tmp_path_factory.mktemp("library")
    build = quick_start("realikea", "assets", "build")
    assert main([*build.argv[1:], "--out", str(library)]) == 0
    return library


def test_the_quick_start_builds_what_the_viewer_opens(quick_start_library):
    viewer = quick_start("python3", "-m", "mujoco.viewer")
    model = viewer.argv[-1].split("=", 1)[1].removeprefix("outputs/assets/")
    assert (quick_start_library / model).is_file()
    assert (quick_start_library / model).with_name("model_hull.xml").is_file()


def test_the_quick_start_trains_two_iterations(quick_start_library, tmp_path):
    train = quick_start("python3", "train.py")
    extra = [*TINY, f"paths.library={quick_start_library}", f"hydra.run.dir={tmp_path}"]
    out = subprocess.run(
        [sys.executable, *replaced(train.argv[1:], extra)],
        cwd=WORKSPACE,
        capture_output=True,
        text=True,
    )
    assert out.returncode == 0, out.stderr[-3000:]
    assert (tmp_path / "model_1.pt").is_file()


def test_the_quick_start_evaluation_loads_its_checkpoint():
    evaluation = quick_start("realikea", "eval")
    cfg, policy = eval_setup(list(target(evaluation.argv).args))
    assert (cfg.asset.category, cfg.asset.kind, cfg.episodes) == ("two_point", "flap", 4)
    assert hasattr(policy, "run_cfg")
