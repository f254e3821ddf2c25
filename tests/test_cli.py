"""The command line: --help starts nothing; run, sweep and report through real processes."""

from __future__ import annotations

import dataclasses
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

from docking.study.readme import README_END, README_START, replace_block, update_readme

REPO = Path(__file__).resolve().parent.parent
TINY_ARGS = ["--train-trials", "4", "--test-trials", "3", "--eval-every", "2", "--eval-trials", "2"]


def _env(tmp_path, columns=250):
    return {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
        "DOCKING_RESULTS": str(tmp_path / "results"),
        "DOCKING_FIGURES": str(tmp_path / "figures"),
        "COLUMNS": str(columns),  # help text on one line per option
    }


def _cli(args, tmp_path, module="docking", timeout=300, columns=250):
    return subprocess.run(
        [sys.executable, "-m", module, *args],
        cwd=tmp_path,
        env=_env(tmp_path, columns),
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def _cli_on_a_terminal(args, tmp_path, timeout=300):
    """Run the CLI with stderr on a pseudo-terminal (where progress bars are drawn); its
    exit status, stdout and what reached the terminal."""
    import fcntl
    import pty
    import struct
    import termios
    import threading

    master, slave = pty.openpty()
    # A terminal 120 columns wide (a new pty has none: a bar would get no width).
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 120, 0, 0))
    chunks = []

    def read():
        while True:
            try:
                data = os.read(master, 65536)
            except OSError:  # the terminal closed
                return
            if not data:
                return
            chunks.append(data)

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    try:
        out = subprocess.run(
            [sys.executable, "-m", "docking", *args],
            cwd=tmp_path,
            env=_env(tmp_path),
            stdout=subprocess.PIPE,
            stderr=slave,
            text=True,
            timeout=timeout,
        )
    finally:
        os.close(slave)
        reader.join(timeout=10)
        os.close(master)
    return out.returncode, out.stdout, b"".join(chunks).decode("utf-8", "replace")


@pytest.mark.parametrize(
    "args",
    [
        [],
        ["run"],
        ["run", "experiment2"],
        ["run", "experiment2", "--help-all"],
        ["sweep"],
        ["sweep", "experiment1"],
        ["report"],
        ["design"],
        ["design", "run"],
        ["design", "list"],
        ["figures"],
        ["ledger"],
        ["verify"],
        ["benchmark"],
    ],
    ids=lambda a: " ".join(a) or "top",
)
def test_help_prints_usage_and_starts_nothing(args, tmp_path):
    start = time.monotonic()
    out = _cli([*args, "--help"], tmp_path, timeout=60, columns=90)  # one column of options
    elapsed = time.monotonic() - start
    assert out.returncode == 0, out.stderr
    assert "usage:" in out.stdout
    assert not (tmp_path / "results").exists() and not (tmp_path / "figures").exists()
    assert list(tmp_path.iterdir()) == []
    assert elapsed < 20, f"--help took {elapsed:.1f} s"
    assert _options_without_help(out.stdout) == []
    assert _defaults_stated_twice(out.stdout) == []
    # A configuration's optional parts are options, not a choice of subcommands.
    assert not {"world-config", "none"} & set(_subcommand_choices(out.stdout))


@pytest.mark.parametrize(
    "args", [["report"], ["run", "experiment1"], ["design", "run"]], ids=" ".join
)
def test_help_descriptions_are_not_broken_mid_sentence(args, tmp_path):
    """Each description is wrapped to its panel's width and nowhere else: tyro 1.0 alone broke
    one wherever its docstring's next line did not begin with a letter (every continued line
    of an option's docstring, and one beginning ``_,`` or ``25-action``)."""
    out = _cli([*args, "--help"], tmp_path, timeout=60, columns=90)
    assert out.returncode == 0, out.stderr
    assert _broken_lines(out.stdout) == []


def _broken_lines(text: str) -> list[str]:
    """The lines of a tyro help text's descriptions after which the next line's first word
    would have fitted (a greedy wrap puts it there): a line break the text itself made."""
    raw = [line.removeprefix("│").rstrip("│ ") for line in text.splitlines()]
    width, broken = 0, []
    for k, (line, after) in enumerate(zip(raw, raw[1:], strict=False)):
        if line.startswith("╭"):  # a panel: its widest line is (at most) its width
            end = next(j for j in range(k, len(raw)) if raw[j].startswith("╰"))
            width = max(len(x) for x in raw[k + 1 : end])
        starts = re.search(r"^ -\S.*?\s{2,}(?=\S)", line) if line.startswith(" -") else None
        column = starts.end() if starts else len(line) - len(line.lstrip())
        indent = len(after) - len(after.lstrip())
        wrapped = after.strip() and indent > 1 and column == indent and len(line) > column
        if wrapped and len(line) + 1 + len(after.split()[0]) <= width:
            broken.append(line.strip())
    return broken


def _help_entries(text: str, joined: bool = True) -> dict:
    """Each option (and positional argument) of a tyro help text: its signature and its
    description, the lines that follow it up to the next entry or the panel's end joined
    (else as a list of its non-empty lines)."""
    raw = [line.removeprefix("│").rstrip("│ ") for line in text.splitlines()]
    entries: dict[str, list[str]] = {}
    current, positional = None, False
    for line in raw:
        if line.startswith(("╭", "╰")):
            current, positional = None, "positional arguments" in line
            continue
        starts = line.startswith(" -") or (positional and line[:2].strip() and line[1] != " ")
        if starts and positional and current is not None and not entries[current]:
            continue  # a positional argument's signature wrapped onto a second line
        if starts:
            signature, _, rest = line.strip().partition("  ")
            current = signature
            entries[current] = [rest.strip()] if rest.strip() else []
        elif current is not None and line.strip():
            entries[current].append(line.strip())
    return {k: " ".join(v) for k, v in entries.items()} if joined else entries


def _defaults_stated_twice(text: str) -> list[str]:
    """The entries of a tyro help text without one readable default: their own words state a
    default besides tyro's "(default: ...)", tyro's shows nothing ("(default: )"), or the
    signature offers None as a value ("{None}|STR")."""
    found = []
    for signature, description in _help_entries(text).items():
        words, hint, shown = description.rpartition("(default:")
        twice = hint and re.search(r"\bdefault", words, re.IGNORECASE)
        unreadable = "{None}" in signature or (hint and not shown.strip(" )"))
        if twice or unreadable:
            found.append(signature.split()[0].rstrip(","))
    return found


def _subcommand_choices(text: str) -> list[str]:
    """The names a tyro help text offers as subcommands (its "• name" lines)."""
    return re.findall(r"^│\s+• (\S+)", text, re.MULTILINE)


def _options_without_help(text: str) -> list[str]:
    """The options of a tyro help text whose description (after the option on its line, or
    on the next line) is missing: another option, the panel's end, or only the default."""
    # an option starts one space inside the panel, its wrapped description further in
    raw = [line.removeprefix("│").rstrip("│ ") for line in text.splitlines()]
    lines = [line.strip() for line in raw]
    missing = []
    for k, (line, after) in enumerate(zip(lines, lines[1:] + [""], strict=True)):
        if not (line.startswith("-") and raw[k].startswith(" -")):
            continue
        signature, _, same_line = line.partition("  ")
        described = same_line.strip() or after
        is_option = not same_line.strip() and k + 1 < len(raw) and raw[k + 1].startswith(" -")
        if not described or is_option or described.startswith(("╰", "╭", "(default")):
            missing.append(signature.split()[0].rstrip(","))
    return missing


def test_the_help_check_finds_an_option_without_help():
    text = "╭─ options ─╮\n│ --a INT │\n│   Says. (default: 1) │\n│ --b INT │\n│   (default: 2) │\n"
    text += "│ -h, --help    show this │\n│ --d INT       (default: 3) │\n"
    assert _options_without_help(text + "│ --c INT │\n╰──╯\n") == ["--b", "--d", "--c"]


def test_the_help_check_finds_a_default_stated_twice():
    text = (
        "╭─ positional arguments ─╮\n│ [{a,b} ...]  Names. (default: ) │\n╰──╯\n"
        "╭─ options ─╮\n│ --a INT │\n│   Says, 3 by default. (default: 3) │\n"
        "│ --b {None}|INT  Says. (default: None) │\n│ --c INT  Plain. (default: 1) │\n"
        '│ --d STR │\n│   "x" (default): the x; "y": │\n│   the y. (default: x) │\n'
        "│ --e INT  Default 0: zero. (default: 0) │\n│ --f STR  Says. (default: the one) │\n"
        "╰──╯\n"
    )
    assert _defaults_stated_twice(text) == ["[{a,b}", "--a", "--b", "--d", "--e"]


def test_the_help_check_finds_subcommands():
    text = "╭─ subcommands ─╮\n│ The world. │\n│   • world-config  Say. │\n│   • none │\n╰──╯\n"
    assert _subcommand_choices(text) == ["world-config", "none"]


@pytest.mark.slow
def test_help_lists_subcommands_and_overrides(tmp_path):
    top = _cli(["--help"], tmp_path).stdout
    for name in ("run", "sweep", "design", "report", "figures", "ledger", "verify", "benchmark"):
        assert name in top
    # One column of options: a default wrapped onto the next line stays next to its option.
    run = _cli(["run", "experiment2", "--help"], tmp_path, columns=100).stdout
    flat = " ".join(run.replace("│", " ").split())
    assert "--network.eps-w" in run and "--seeds" in run
    assert "--train-trials INT" in flat and "(default: 2000)" in flat


@pytest.mark.slow
def test_bad_input_is_a_clear_error(tmp_path):
    out = _cli(["run", "experiment1", "--seeds", "5-2"], tmp_path)
    assert out.returncode == 2 and "seeds must be" in out.stderr
    out = _cli(["sweep", "experiment1", "--grid", "network.nope=1"], tmp_path)
    assert out.returncode == 2 and "NetworkConfig.nope" in out.stderr
    out = _cli(["run", "experiment1", "--network.eps-w", "-1"], tmp_path)
    assert out.returncode == 2 and "NetworkConfig.eps_w" in out.stderr
    for args, says in (
        (["run", "experiment1", "--seeds", "0-9999999"], "at most 10000 seeds"),
        (["run", "experiment1", "--seeds", "0", "--scheduler", "http://x:1"], "tcp://HOST:PORT"),
        (["run", "experiment1", "--network.beta-s", "1" + "0" * 400], "NetworkConfig.beta_s"),
        (["run", "experiment1", "--network.eps-q", "1e300"], "NetworkConfig.eps_q"),
        (["run", "experiment1", "--world.view-margin-px", "100"], "view_margin_px"),
        (["verify", "--sample", "-1"], "--sample"),
    ):
        out = _cli(args, tmp_path)
        assert out.returncode == 2 and says in out.stderr, (args, out.stderr)
        assert "Traceback" not in out.stderr
    out = _cli(["benchmark", "--steps", "-5"], tmp_path)
    assert out.returncode == 2 and "--steps must be" in out.stderr
    assert not (tmp_path / "results").exists()


@pytest.mark.slow
def test_run_stores_runs_and_loads_them_again(tmp_path):
    args = ["run", "experiment1", "--seeds", "0-1", "--processes", "1", *TINY_ARGS]
    out = _cli([*args, "--network.eps-w", "0"], tmp_path)
    assert out.returncode == 0, out.stderr
    # The line names the options that differ from the preset (issue 44).
    assert out.stdout.startswith("experiment1 (--network.eps-w 0.0, --train-trials 4, ")
    assert "): test success mean" in out.stdout
    files = sorted((tmp_path / "results").rglob("seed*.npz"))
    assert [f.name for f in files] == ["seed0.npz", "seed1.npz"]
    # No bar when stderr is not a terminal (its unit, trials, is not named), but a line per
    # run finished (issue 62)
    assert "trial" not in out.stderr and "\r" not in out.stderr
    assert "experiment1, 2 seeds: run 2/2 done, computed (experiment1 seed 1); " in out.stderr
    store = files[0].parent
    assert out.stdout.splitlines()[-1] == f"seeds 0-1: computed now and stored in {store}"
    mtimes = [f.stat().st_mtime_ns for f in files]
    again = _cli([*args, "--network.eps-w", "0"], tmp_path)
    assert again.returncode == 0
    assert again.stdout.splitlines()[0] == out.stdout.splitlines()[0]  # the same runs
    assert again.stdout.splitlines()[-1] == f"seeds 0-1: loaded from the results store, {store}"
    assert [f.stat().st_mtime_ns for f in files] == mtimes  # loaded, not recomputed
    # On a terminal the bar counts trials: a new seed shows its trials as they finish.
    status, stdout, terminal = _cli_on_a_terminal(
        [*args[:3], "2", *args[4:], "--network.eps-w", "0"], tmp_path
    )
    assert status == 0, terminal
    assert "experiment1, 1 seeds" in terminal and "trial" in terminal and "runs 1/1" in terminal


#: The configurations run names besides the paper's experiments (issue 62).
WORLD_NAMES = ("floor", "floor-tuned", "floor-linear", "nao", "nao-tuned", "nao-linear")


def test_run_names_the_worlds_published_settings_and_tuned_learners(tmp_path):
    """Issue 62: ``run`` names Experiment 2 in the floor and Nao-like worlds, the paper's
    learner at its published settings (the designs' experiment2_in) and the tuned learners
    (``run floor`` failed); its help lists each, with what it is, on a screen."""
    from docking.presets import EXPERIMENT_2, FLOOR_WORLD, NAO_WORLD, SEEDS
    from docking.study.cli import named, parse
    from docking.study.cli.runs import _label, _seeds_of
    from docking.study.designs.builders import experiment2_in

    for world, base in (("floor", FLOOR_WORLD), ("nao", NAO_WORLD)):
        config = parse(["run", world]).experiment
        assert config == experiment2_in(base, world) and config.network == EXPERIMENT_2.network
        assert _seeds_of(config, None) == list(SEEDS["experiment2"])
        for suffix, learner in (("tuned", "paper"), ("linear", "linear")):
            name = f"{world}-{suffix}"
            config = parse(["run", name]).experiment
            assert config == named.tuned(world, learner) and config.name == name
            assert config.network != EXPERIMENT_2.network
            assert _label(config) == name  # no option differs from its namesake
            assert _seeds_of(config, None) == list(SEEDS["experiment2"])
    assert parse(["run", "nao-tuned", "--network.eps-w", "0"]).experiment.network.eps_w == 0
    assert parse(["sweep", "floor-linear"]).experiment.name == "floor-linear"
    out = _cli(["run", "--help"], tmp_path, timeout=60, columns=80)
    assert out.returncode == 0, out.stderr
    for name in ("experiment1", "experiment2", *WORLD_NAMES):
        assert f"• {name} " in out.stdout, name
    flat = " ".join(out.stdout.replace("│", " ").split())
    assert "floor-tuned the paper's learner, tuned (equal-contest), floor world." in flat
    assert "nao-linear linear SARSA, tuned (equal-contest), Nao-like world." in flat
    assert "nao the paper's learner, published settings, Nao-like world." in flat
    assert len(out.stdout.splitlines()) <= 45  # a screen, at 80 columns


def test_the_tuned_entries_are_the_published_designs_tuned_learners(monkeypatch):
    """The one table of the tuned entries (named.TUNED, a copy) is the design it names, the
    equal contest: its chosen settings read from the committed ledger, each entry that
    learner's judged network in Experiment 2 of the world. When the table is repointed to a
    later design, this test is."""
    from docking.study.cli import named
    from docking.study.designs import equal_contest as ec
    from docking.study.designs import equal_contest_report as ecr
    from docking.study.designs.builders import experiment2_in

    monkeypatch.setenv("DOCKING_LEDGER", str(REPO / "ledger"))
    results = ec.DESIGN.read()
    chosen = ecr.chosen(results)
    assert named.TUNED[0] == ec.NAME
    assert named.TUNED[1] == {
        world: {learner: chosen[world, learner] for learner in ("paper", "linear")}
        for world in named.WORLDS
    }
    for world, (_, base) in named.WORLDS.items():
        for learner in ("paper", "linear"):
            config = named.tuned(world, learner)
            network = results.cell(f"{world}/{learner}/judged").config.network
            assert config == dataclasses.replace(experiment2_in(base, config.name), network=network)


def test_the_tuned_entries_follow_their_table(monkeypatch):
    """Repointed (here to a stand-in table), the tuned entries are its settings under their
    own names, the help names its design; the published settings stay."""
    from docking.study.cli import named

    settings = {"paper": {"eps_q": 0.2}, "linear": {"eps_q": 0.4}}
    monkeypatch.setattr(named, "TUNED", ("a-later-design", dict.fromkeys(named.WORLDS, settings)))
    found = named.named()
    assert list(found) == list(WORLD_NAMES)
    assert found["nao-tuned"][0].network.eps_q == 0.2 and found["nao-tuned"][0].name == "nao-tuned"
    assert found["floor-linear"][0].network.eps_q == 0.4
    assert found["floor-linear"][0].network.feature_layer == "none"  # linear SARSA
    assert found["floor-tuned"][1] == "the paper's learner, tuned (a-later-design), floor world"
    assert found["floor"][0] == named.published("floor") and found["floor"][0].name == "floor"


def test_the_command_line_starts_without_scipy(tmp_path):
    """Naming the worlds' entries costs no import of a design file (which imports SciPy) at
    the start of every command."""
    code = "import sys, docking.study.cli; print(sorted(m for m in sys.modules if 'scipy' in m))"
    out = subprocess.run(
        [sys.executable, "-c", code], env=_env(tmp_path), capture_output=True, text=True, timeout=60
    )
    assert out.returncode == 0 and out.stdout.strip() == "[]", out.stderr[-2000:]


@pytest.mark.parametrize(
    "args, experiment",
    [
        (["--help"], False),
        (["ledger", "--help"], False),
        (["verify", "--help"], False),
        (["report", "--help"], False),
        (["design", "list", "--help"], False),
        (["run", "experiment1", "--help"], True),
        (["sweep", "--help"], True),
    ],
    ids=lambda a: " ".join(a) if isinstance(a, list) else str(a),
)
def test_a_command_imports_the_experiments_modules_only_if_they_are_its_options(
    args, experiment, tmp_path
):
    """Issue 61: every command imported every command's modules, and with them the
    experiment's (NumPy, MuJoCo), before it parsed its command line (and ``import docking``
    NumPy with Gymnasium); now only a command whose options are an experiment's fields (run,
    sweep) imports them to parse."""
    code = (
        "import sys\n"
        "from docking.study.cli import main\n"
        "try:\n"
        "    main(sys.argv[1:])\n"
        "except SystemExit:\n"
        "    pass\n"
        "found = ('numpy', 'mujoco', 'docking.experiments', 'docking.study.cli.named')\n"
        "print(sorted(m for m in found if m in sys.modules), file=sys.stderr)\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code, *args],
        env=_env(tmp_path, columns=90),
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert out.returncode == 0 and "usage:" in out.stdout, out.stderr
    every = str(sorted(("numpy", "mujoco", "docking.experiments", "docking.study.cli.named")))
    assert out.stderr.strip().splitlines()[-1] == (every if experiment else "[]")


@pytest.mark.slow
def test_run_runs_a_world_by_name(tmp_path):
    args = ["run", "nao-linear", "--seeds", "0", "--processes", "1", "--train-trials", "2"]
    out = _cli([*args, "--test-trials", "2", "--curriculum.grow-trials", "2"], tmp_path)
    assert out.returncode == 0, out.stderr
    first, last = out.stdout.splitlines()[0], out.stdout.splitlines()[-1]
    assert first.startswith("nao-linear (--curriculum.grow-trials 2, --train-trials 2, ")
    assert "): test success mean" in first
    (stored,) = (tmp_path / "results" / "nao-linear").rglob("seed0.npz")
    assert last == f"seeds 0: computed now and stored in {stored.parent}"


def test_run_says_a_run_came_from_the_ledger(tmp_path, monkeypatch):
    # The committed ledger holds the paper's Experiment 1: nothing is computed or stored, and
    # the output says where the runs came from (it named an empty store folder before).
    monkeypatch.setenv("DOCKING_LEDGER", str(REPO / "ledger"))
    out = _cli(["run", "experiment1", "--seeds", "0,1,3"], tmp_path)
    assert out.returncode == 0, out.stderr
    assert out.stdout.splitlines()[-1] == (
        f"seeds 0-1, 3: read from the committed ledger, {REPO / 'ledger'} (its files checked "
        "against their SHA-256, its digests and wall times against their seal; nothing computed)"
    )
    assert not list((tmp_path / "results").rglob("*.npz"))


@pytest.mark.slow
def test_sweep_runs_every_grid_point(tmp_path):
    grid = ["--grid", "network.eps_w=0,0.05", "world.step_noise_xy=0.0,0.01"]
    out = _cli(
        ["sweep", "experiment1", "--seeds", "2", "--processes", "1", *TINY_ARGS, *grid], tmp_path
    )
    assert out.returncode == 0, out.stderr
    lines = out.stdout.strip().splitlines()
    assert len(lines) == 8  # per grid point its success, then where its runs came from
    assert all(line.startswith("  seeds 2: computed now and stored in ") for line in lines[1::2])
    assert len(list((tmp_path / "results").rglob("seed2.npz"))) == 4


def test_sweep_says_which_runs_came_from_the_ledger(tmp_path, monkeypatch):
    # eps_W 0.05 is Experiment 1's own, whose seed 0 the committed ledger holds: read, not
    # computed, and no store folder is named for it (it named one that did not exist).
    monkeypatch.setenv("DOCKING_LEDGER", str(REPO / "ledger"))
    grid = ["--grid", "network.eps_w=0.05"]
    out = _cli(["sweep", "experiment1", "--seeds", "0", "--processes", "1", *grid], tmp_path)
    assert out.returncode == 0, out.stderr
    assert out.stdout.splitlines()[1] == (
        f"  seeds 0: read from the committed ledger, {REPO / 'ledger'} (its files checked "
        "against their SHA-256, its digests and wall times against their seal; nothing computed)"
    )
    assert not (tmp_path / "results").exists() or not list((tmp_path / "results").rglob("*"))


def test_replace_block():
    text = f"# T\n\nbefore\n{README_START}\nold\n{README_END}\nafter\n"
    assert replace_block(text, "| new |\n") == (
        f"# T\n\nbefore\n{README_START}\n| new |\n{README_END}\nafter\n"
    )
    for bad in ("no markers", f"{README_END}\n{README_START}", f"{README_START}{README_START}"):
        with pytest.raises(ValueError, match="must hold one"):
            replace_block(bad, "x")


def test_update_readme(tmp_path):
    readme = tmp_path / "README.md"
    readme.write_text(f"a\n{README_START}\n{README_END}\nb\n")
    assert update_readme(readme, "| t |") is True
    assert readme.read_text() == f"a\n{README_START}\n| t |\n{README_END}\nb\n"
    assert update_readme(readme, "| t |") is False


def test_project_readme_has_the_markers():
    from docking.study import readme

    text = (REPO / "README.md").read_text()
    for start, end in (
        (README_START, README_END),
        (readme.TIMINGS_START, readme.TIMINGS_END),
        (readme.SUMMARY_START, readme.SUMMARY_END),
        (readme.GLANCE_START, readme.GLANCE_END),
        (readme.VERDICTS_START, readme.VERDICTS_END),
    ):
        assert text.count(start) == 1 and text.count(end) == 1
    # The detail on the site's findings page, one link from the README's summary
    page = (REPO / readme.FINDINGS_PAGE).read_text()
    for start, end in (
        (readme.DETAILS_START, readme.DETAILS_END),
        (readme.THIRD_EDITION_START, readme.THIRD_EDITION_END),
        (readme.EXPERIMENT3_START, readme.EXPERIMENT3_END),
    ):
        assert page.count(start) == 1 and page.count(end) == 1 and start not in text
    summary = text[text.index(readme.SUMMARY_START) : text.index(readme.SUMMARY_END)]
    assert f"]({readme.FINDINGS_PAGE})" in summary
    # The answer first: the first screen's figure and sentences, then the two commands,
    # within the first 30 lines; the detailed summary before how to run anything.
    first = text[: text.index(readme.GLANCE_END)]
    assert first.count("\n") < 30 and text.index(readme.GLANCE_END) < text.index("```bash")
    figure = re.search(r"!\[[^]]+\]\((figures/[^)]+\.png)\)", first)
    assert figure and (REPO / figure.group(1)).is_file(), "the first screen has no figure"
    sentences = first[first.index(readme.GLANCE_START) :].split("\n")
    assert len([line for line in sentences if re.match(r"\d\. ", line)]) <= 5
    assert text.index(readme.SUMMARY_START) < text.index("## Start here")
    # No verdict table of an archived edition; the third edition's will be the one
    assert "| claim, in the paper's words | verdict |" not in text
    assert "second-edition:start" not in text


def test_timings_paragraph_says_what_was_measured():
    from docking.study.readme import timings_text

    record = {
        "date": "2026-01-02",
        "commit": "abcdef0123",
        "cores": 2,
        "python": "3.11.7",
        "step": {"min_ms": 0.3, "median_ms": 0.35},
        "tiers": {"setup": {"wall_s": 480.0, "cpu_s": 100.0}, "test": {"wall_s": 900, "cpu_s": 1}},
    }
    text = timings_text(record, 300, 7200.0)
    assert "on 2026-01-02" in text and "commit abcdef0" in text and "2-core" in text
    assert "0.30 / 0.35 ms" in text
    assert "`make setup` 8.0 min (package downloads); `make test` 15.0 min." in text
    assert "300 runs" in text and "2.0 h of one process (24 s per run" in text
    assert "have not been timed" in timings_text(None, 300, 7200.0)
    assert "the ledger (3.0 MiB, compressed;" in timings_text(
        None, 300, 7200.0, ledger_bytes=3 * 2**20
    )
    record["tiers"] |= {"docs": {"wall_s": 270.0}, "report": {"wall_s": 14.2}}
    text = timings_text(record, 300, 7200.0)
    assert "`make docs` 4.5 min (the site, executing the notebooks" in text
    assert "`python -m docking report` 14 s (from the committed ledger)" in text
    record["tiers"]["setup"]["commit"] = "0123456789"  # kept from an earlier measurement
    assert "`make setup` 8.0 min (package downloads), on 0123456;" in timings_text(record, 1, 1.0)


def test_report_refuses_to_start_a_computation_without_compute(tmp_path):
    env_off = {"DOCKING_LEDGER": "off"}
    os.environ.update(env_off)
    try:
        out = _cli(["report"], tmp_path, timeout=120)
    finally:
        del os.environ["DOCKING_LEDGER"]
    assert out.returncode == 2, out.stderr
    assert "--compute" in out.stderr and "Traceback" not in out.stderr
    assert (
        not list((tmp_path / "results").rglob("*.npz")) if (tmp_path / "results").exists() else True
    )


def test_design_list_names_every_design(tmp_path):
    out = _cli(["design", "list"], tmp_path, timeout=120)
    assert out.returncode == 0, out.stderr
    for name in ("paper", "calibration-experiment1", "experiment3", "experiment3-oracle"):
        assert name in out.stdout
    assert "second-edition" not in out.stdout  # archived: read at 1341e99


def test_figures_refuses_runs_it_does_not_have(tmp_path):
    os.environ["DOCKING_LEDGER"] = "off"
    try:
        out = _cli(["figures", "--folder", str(tmp_path / "f")], tmp_path, timeout=120)
    finally:
        del os.environ["DOCKING_LEDGER"]
    assert out.returncode == 2 and "neither stored nor in the ledger" in out.stderr
    assert not (tmp_path / "f").exists()


def test_an_installed_package_says_how_to_get_the_ledger(tmp_path, monkeypatch):
    """A wheel carries no ledger (it is the checkout's ledger/ folder): report and figures,
    which read their runs from it, say what to do instead of only refusing."""
    import shutil

    site = tmp_path / "site"  # the package as pip installs it: no pyproject.toml beside it
    shutil.copytree(REPO / "docking", site / "docking", ignore=shutil.ignore_patterns("*.pyc"))
    monkeypatch.delenv("DOCKING_LEDGER")
    env = {**_env(tmp_path), "PYTHONPATH": str(site)}
    for args in (["figures", "--folder", str(tmp_path / "f")], ["report"]):
        out = subprocess.run(
            [sys.executable, "-m", "docking", *args],
            cwd=tmp_path,
            env=env,
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert out.returncode == 2 and "Traceback" not in out.stderr, out.stderr
        says = " ".join(out.stderr.split())
        assert "This installed package has no ledger" in says, says
        assert "clone the repository" in says and "DOCKING_LEDGER" in says, says
        assert "python -m docking run" in says or "--compute" in says, says
    assert not (tmp_path / "f").exists() and not list(tmp_path.rglob("*.npz"))
    # With the ledger switched off, the error says so (and how to switch it on).
    monkeypatch.setenv("DOCKING_LEDGER", "off")
    out = _cli(["figures", "--folder", str(tmp_path / "f")], tmp_path, timeout=120)
    assert out.returncode == 2 and "DOCKING_LEDGER=off" in out.stderr, out.stderr


def test_every_folder_of_the_package_is_declared_and_the_wheels_folder_is_ignored():
    """Issue 52: setuptools warned that the folder docking/assets "would be ignored" (it was
    absent from ``packages``), and the wheel the README builds into dist/ showed as untracked.
    Every folder of the package is a declared package whose data files its package-data
    names, and git ignores dist/."""
    import fnmatch
    import tomllib

    setuptools = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["setuptools"]
    packages, data = set(setuptools["packages"]), setuptools["package-data"]
    package = REPO / "docking"
    folders = [package] + sorted(
        p for p in package.rglob("*") if p.is_dir() and "__pycache__" not in p.parts
    )
    for folder in folders:
        name = ".".join(folder.relative_to(REPO).parts)
        assert name in packages, name
        for path in folder.iterdir():
            if path.is_file() and path.suffix not in (".py", ".pyc"):
                assert any(fnmatch.fnmatch(path.name, p) for p in data.get(name, ())), path
    ignored = subprocess.run(
        ["git", "check-ignore", "-q", "dist/docking-0.1.0-py3-none-any.whl"], cwd=REPO
    )
    if ignored.returncode == 128:  # not a git checkout
        pytest.skip("not a git checkout")
    assert ignored.returncode == 0, "dist/ is not ignored by git"


def test_help_is_plain_text(tmp_path):
    """Option help comes from the config dataclasses' docstrings: no Sphinx markup there."""
    out = _cli(["run", "experiment2", "--help"], tmp_path, timeout=60)
    assert out.returncode == 0
    for markup in ("``", ":class:", ":func:", ":data:", ":attr:", ":meth:"):
        assert markup not in out.stdout, markup


def _choice_checks() -> set[tuple[str, str]]:
    """(class, field) of every check_choice(owner, "field", ...) call in a class's methods."""
    import ast

    import docking

    found = set()
    for path in Path(docking.__file__).parent.rglob("*.py"):
        for cls in ast.walk(ast.parse(path.read_text())):
            if not isinstance(cls, ast.ClassDef):
                continue
            for call in ast.walk(cls):
                if (
                    isinstance(call, ast.Call)
                    and getattr(call.func, "id", None) == "check_choice"
                    and isinstance(call.args[1], ast.Constant)
                ):
                    found.add((cls.name, call.args[1].value))
    return found


def test_every_named_value_field_is_a_choice_on_the_command_line():
    from docking.study.cli.named import CHOICES

    table = {(cls.__name__, name) for cls, fields in CHOICES.items() for name in fields}
    assert table == _choice_checks()


@pytest.mark.slow
def test_named_values_are_shown_and_checked_as_choices(tmp_path):
    help_text = _cli(["run", "experiment2", "--help"], tmp_path, timeout=60).stdout
    for option in ("--world.scene {sideboard,floor}", "--network.rule {local,nonlocal}"):
        assert option in help_text
    out = _cli(["run", "experiment2", "--world.scene", "flor"], tmp_path, timeout=60)
    assert out.returncode == 2 and "invalid choice 'flor'" in out.stderr
    assert "--world.scene" in out.stderr and "__tyro" not in out.stderr
    assert not (tmp_path / "results").exists()


def _tracked_files(checkout: Path) -> dict[str, tuple]:
    """``{path: (inode, modification time, SHA-256)}`` of every file git tracks in
    ``checkout``, and git's status (a file rewritten with the same bytes moves its time, a
    file replaced atomically its inode; a new file shows in the status)."""
    import hashlib

    def git(*args) -> str:
        return subprocess.run(
            ["git", *args], cwd=checkout, capture_output=True, text=True, check=True
        ).stdout

    found = {}
    for name in filter(None, git("ls-files", "-z").split("\0")):
        path = checkout / name
        stat = path.stat()
        found[name] = (stat.st_ino, stat.st_mtime_ns, hashlib.sha256(path.read_bytes()).hexdigest())
    found["(git status)"] = git("status", "--porcelain", "--untracked-files=all")
    return found


@pytest.mark.slow
def test_report_without_readme_or_figures_writes_no_file_of_the_checkout(tmp_path):
    """Issue 60: `python -m docking report` (no --readme) rewrote figures/glance.png and .pdf
    (and the claims at a glance) from the ledger. Run from a checkout of its own (the
    package, its figures and README committed to a fresh git repository; this checkout's
    notebooks rewrite figures/ while make test runs), reading the committed ledger: it
    writes no file of the checkout; asked to (--figures-dir), it writes its figures there,
    and still none of the checkout's."""
    import shutil

    checkout = tmp_path / "checkout"
    shutil.copytree(REPO / "docking", checkout / "docking", ignore=shutil.ignore_patterns("*.pyc"))
    shutil.copytree(REPO / "figures", checkout / "figures")
    for name in ("pyproject.toml", "README.md", ".gitignore"):
        shutil.copy(REPO / name, checkout / name)
    git = ["git", "-c", "user.name=t", "-c", "user.email=t@t", "-C", str(checkout)]
    for args in (["init", "-q"], ["add", "-A"], ["commit", "-q", "-m", "checkout"]):
        subprocess.run([*git, *args], check=True, capture_output=True)
    env = {**_env(tmp_path), "DOCKING_LEDGER": str(REPO / "ledger"), "PYTHONPATH": str(checkout)}
    del env["DOCKING_FIGURES"], env["DOCKING_RESULTS"]  # the checkout's figures/ and results/
    before = _tracked_files(checkout)
    assert "figures/glance.png" in before and not before["(git status)"]
    for args in (["report"], ["report", "--figures-dir", str(tmp_path / "asked")]):
        out = subprocess.run(
            [sys.executable, "-m", "docking", *args],
            cwd=tmp_path,
            env=env,
            capture_output=True,
            text=True,
            timeout=1200,
        )
        assert out.returncode == 0, out.stderr[-3000:]
        assert "](figures/glance.png)" in out.stdout  # the README's block still links it
        after = _tracked_files(checkout)
        changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
        assert not changed, f"{' '.join(args)} changed {changed[:10]}: {after['(git status)']}"
    written = sorted(p.name for p in (tmp_path / "asked").iterdir())
    for name in ("glance", "verdicts_glance", "fig3_experiment1"):
        assert f"{name}.png" in written and f"{name}.pdf" in written, written


@pytest.mark.slow
def test_the_readme_is_what_report_writes_from_the_ledger(tmp_path):
    """Every number of the README's blocks (the summary, the results, Experiment 3, the third
    edition, the verdicts, the timings) is what `report --readme` writes from the committed
    ledger: run on a copy, it changes nothing."""
    from docking.study.readme import FINDINGS_PAGE, VERDICTS_PAGE

    copy = tmp_path / "README.md"
    copy.write_text((REPO / "README.md").read_text())
    page = tmp_path / VERDICTS_PAGE  # the full verdict table, beside the README
    page.parent.mkdir(parents=True)
    page.write_text((REPO / VERDICTS_PAGE).read_text())
    details = tmp_path / FINDINGS_PAGE  # what the runs show in detail, beside the README
    details.write_text((REPO / FINDINGS_PAGE).read_text())
    out = subprocess.run(
        [sys.executable, "-m", "docking", "report", "--readme", str(copy)],
        cwd=tmp_path,
        env={**_env(tmp_path), "DOCKING_LEDGER": str(REPO / "ledger")},  # the tests' is off
        capture_output=True,
        text=True,
        timeout=1200,
    )
    assert out.returncode == 0, out.stderr[-3000:]
    assert copy.read_text() == (REPO / "README.md").read_text()
    assert page.read_text() == (REPO / VERDICTS_PAGE).read_text()
    assert details.read_text() == (REPO / FINDINGS_PAGE).read_text()
    assert f"{copy}: already up to date" in out.stdout


def test_ledger_show_counts_runs_configurations_and_tables(capsys, monkeypatch):
    """``ledger show`` counts what the committed manifest holds: its runs, their distinct
    configurations and the results tables (it once called the tables "configurations")."""
    from docking.study import ledger
    from docking.study.cli import main

    monkeypatch.setenv("DOCKING_LEDGER", str(REPO / "ledger"))
    data = ledger.manifest()
    assert main(["ledger", "show"]) == 0
    out = " ".join(capsys.readouterr().out.split())  # its lines wrap where the path's length says
    runs, configs, tables = len(data["runs"]), len(data["configs"]), len(data["tables"])
    assert configs > tables  # else the test could not tell them apart
    assert f"{runs} runs (" in out
    assert f"of {configs} configurations in {tables} results tables" in out


def test_design_run_counts_where_its_runs_came_from(tmp_path, monkeypatch):
    """``design run`` ends with how many runs were computed, loaded from the store or read
    from the ledger, in ``run``'s words, and names the store only where a run is in it."""
    from docking.study.cli.runs import _counted

    monkeypatch.setenv("DOCKING_LEDGER", str(REPO / "ledger"))
    ledger = (
        f"read from the committed ledger, {REPO / 'ledger'} (its files checked against their "
        "SHA-256, its digests and wall times against their seal; "
    )
    mixed = _counted({"a": ["ledger", "store"], "b": ["computed", "ledger"]}, tmp_path)
    assert mixed == (
        f"runs: 2 {ledger}nothing computed); 1 loaded from the results store, {tmp_path}; "
        f"1 computed now and stored in {tmp_path}"
    )
    assert _counted({"a": ["ledger"]}, tmp_path) == f"runs: 1 {ledger}nothing computed)"
