"""What every report shares: Markdown tables (:func:`md_table`), a configuration as a table
(:func:`configuration_table`), saving a figure under a name (:func:`save_named`), the gap rule
several designs judge by (:func:`contest_gaps`, :func:`paired_over_shared_seeds`, the table
:func:`gaps_table`), the time of a record (:func:`utc`) and the command that recomputes the
runs behind a number (:func:`verify_command`).

Each design reports itself: its tables, its figures' data and its sentences are in the module
beside its design file, ``docking/study/designs/<design>_report.py`` (the paper's,
calibration's, Experiment 3's, the third edition's, the untested claims', their revisit's, the
addendum's and the bracketing's). The README's own blocks (its markers, the summary, the first
screen, the times) are :mod:`docking.study.readme`; the study's provenance (rules before runs,
deviations) :mod:`docking.study.provenance`. ``python -m docking report``
(:mod:`docking.study.cli`) prints them all and, with ``--readme README.md``, writes each
between its markers.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from matplotlib.figure import Figure

from docking.presets import HEADLINE_SEED, SEEDS
from docking.study import figures
from docking.study.stats import Interval

if TYPE_CHECKING:  # a configuration's fields are read, no run is made
    from docking.experiments import ExperimentConfig


def _pct(x: float) -> str:
    return f"{100 * x:.1f}%"


def _network_choices(config: ExperimentConfig) -> list[tuple[str, str, str]]:
    """The configuration table's rows of the network: units, rule, rates and initial weights."""
    n = config.network
    return [
        ("feature units / rule", f"{n.n_features} / {n.rule}", "paper"),
        (
            "beta_s, beta_a (train, test), gamma",
            f"{n.beta_s:g}, ({n.beta_a_train:g}, {n.beta_a_test:g}), {n.gamma:g}",
            "paper (Eq. 2, 4, 6)",
        ),
        ("eps_q (Eq. 7), eps_w (Eq. 8)", f"{n.eps_q:g}, {n.eps_w:g}", "ours"),
        ("input I", "unit length" if n.normalize_input else "raw", "ours"),
        (
            "initial W / Q",
            f"uniform random, rows unit length / uniform in [0, {n.q_init:g}]",
            "ours",
        ),
    ]


def _training_region(config: ExperimentConfig) -> tuple[str, str]:
    """The configuration table's start region in training (the curriculum) and its source."""
    w, c = config.world, config.curriculum
    if c.grow_trials:
        region = (
            f"far edge {c.far_initial:.2f} m -> {w.start_far:.2f} m, linearly over the "
            f"first {c.grow_trials} trials"
        )
        return region, "ours: the paper says only 'incrementally enlarged', up to 1.5 m"
    return "fixed (no curriculum)", "paper"


def _world_choices(config: ExperimentConfig) -> list[tuple[str, str, str]]:
    """The configuration table's rows of the world: start regions, steps, noise and dock."""
    w = config.world
    return [
        (
            "test start region",
            f"{w.start_near:.2f}-{w.start_far:.2f} m from the landmark, "
            f"+-{w.start_half_angle_deg:g} deg, "
            f"heading +-{w.start_yaw_deg:g} deg",
            "ours (the paper: a trapezoid)",
        ),
        ("start region in training", *_training_region(config)),
        (
            "steps",
            f"forward/back {100 * w.step_forward:.0f} cm, sideways {100 * w.step_side:.0f} cm",
            "ours",
        ),
        (
            "step noise (s.d.)",
            f"{100 * w.step_noise_xy:.0f} cm per axis, {w.step_noise_yaw_deg:g} deg heading",
            "ours",
        ),
        (
            "docking region",
            f"{100 * w.dock_width:.0f} cm across x {100 * w.dock_depth:.0f} cm deep",
            "paper: 8x20 cm",
        ),
    ]


def _run_choices(config: ExperimentConfig) -> list[tuple[str, str, str]]:
    """The configuration table's rows of the runs: trials, SARSA's target, curve and seeds."""
    return [
        (
            "trials",
            f"{config.train_trials} training, {config.test_trials} test, at most "
            f"{config.world.max_steps} actions",
            "paper",
        ),
        (
            "SARSA target at the step limit",
            "bootstrap from v'" if config.bootstrap_on_truncation else "v' = 0",
            "ours",
        ),
        (
            "learning curve",
            f"{config.eval_trials} greedy trials from the test region every "
            f"{config.eval_every} training trials",
            "ours",
        ),
        (
            "seeds",
            f"{SEEDS.get(config.name)}, headline seed {HEADLINE_SEED}",
            "ours (the paper reports one run)",
        ),
    ]


def configuration_table(config: ExperimentConfig) -> str:
    """A Markdown table of every choice behind ``config``: value and whether it is the
    paper's or ours (ours = the paper leaves it open; the reasons are in the notebooks)."""
    rows = [*_network_choices(config), *_world_choices(config), *_run_choices(config)]
    return md_table(("choice", "value", "source"), rows)


def save_named(fig: Figure, name: str, folder: Path | str | None = None) -> str:
    """Save ``fig`` as ``name`` (``.png`` and ``.pdf``) in ``folder`` (default
    :data:`docking.study.figures.FIGURES_DIR`); the PNG's path, for display."""
    png, _ = figures.save_figure(fig, _folder(folder) / name)
    return str(png)


def _folder(folder: Path | str | None) -> Path:
    return figures.FIGURES_DIR if folder is None else Path(folder)


def md_table(header, rows) -> str:
    """A Markdown table: ``header`` (column titles) over ``rows`` (a sequence of cells each;
    cells are shown as ``str`` shows them, a pipe in one escaped by
    :func:`docking.study.claims.markdown_cell`, as the verdict table's are)."""
    from docking.study.claims import markdown_cell

    def line(cells) -> str:
        return "| " + " | ".join(markdown_cell(str(c)) for c in cells) + " |"

    return "\n".join([line(header), "|" + "---|" * len(header)] + [line(r) for r in rows])


def paired_over_shared_seeds(results, key: str, baseline: str) -> Interval:
    """``key`` minus ``baseline`` (per-seed success), paired over the seeds both cells have
    (their first seeds: every cell of a design draws its seeds from the front of one list),
    with the paired Student-t interval."""
    from docking.study.stats import t_paired_ci

    a, b = results.score(key), results.score(baseline)
    n = min(len(a), len(b))
    return t_paired_ci(a[:n], b[:n])


@dataclasses.dataclass(frozen=True)
class ContestGap:
    """The contest's finding in one world: ``other - paper`` (paired over seeds) and what
    the rule makes of it (``"closed"``, ``"remains"``, ``"undecided"``)."""

    world: str
    other: str
    interval: Interval
    verdict: str
    bound: float  # the rule's margin, a fraction

    @property
    def words(self) -> str:
        """The verdict as the test it is (:func:`gap_words`)."""
        return gap_words(self.verdict, self.bound)

    def as_data(self) -> list:
        """``[world, other, estimate, low, high, verdict]``: what a design's record of its
        replay holds of it (:func:`docking.study.designs.replay`)."""
        ci = self.interval
        return [self.world, self.other, ci.estimate, ci.low, ci.high, self.verdict]


def contest_gaps(results, worlds, bound: float, other: str = "linear-tuned") -> list[ContestGap]:
    """Per world: ``other`` minus the tuned paper's learner, paired over the seeds both
    have (Student-t); closed if the interval lies below ``bound``, remains if above it."""
    found = []
    for world in worlds:
        ci = paired_over_shared_seeds(results, f"{world}/{other}", f"{world}/paper-tuned")
        verdict = "closed" if ci.high < bound else "remains" if ci.low > bound else "undecided"
        found.append(ContestGap(world, other, ci, verdict, bound))
    return found


def gap_words(verdict: str, bound: float) -> str:
    """The gap rule's ``verdict`` (:func:`contest_gaps`, at the margin ``bound``, a fraction) as
    the test it is: a one-sided non-inferiority test of the paper's learner at that margin
    (issue 59: the word "closed" is retired from what tables and sentences say; the rules and
    their records keep their verdicts' names)."""
    margin = f"{bound * 100:g} pp"
    return {
        "closed": f"non-inferior at {margin}",
        "remains": f"inferior by more than {margin}",
        "undecided": "undecided",
    }[verdict]


def gaps_table(gaps: list[ContestGap]) -> str:
    """The Markdown table of :func:`contest_gaps`."""
    return md_table(
        ("world", "compared", "minus the tuned paper's learner", "gap"),
        [
            (
                g.world,
                g.other,
                f"{g.interval.format(unit=' pp')} (n = {len(g.interval.values)})",
                g.words,
            )
            for g in gaps
        ],
    )


def utc(text: str):
    """An ISO 8601 time (a run's ``computed_utc``, a commit's ``%cI``) as an aware UTC
    datetime."""
    import datetime

    return datetime.datetime.fromisoformat(text).astimezone(datetime.UTC)


#: How the README names the command line (``python -m docking``).
VERIFY = "python -m docking verify"


def verify_command(design: str, cells: str | Sequence[str] = (), seeds=None) -> str:
    """The command line that recomputes the runs behind a number and compares each with the
    ledger: ``python -m docking verify --design DESIGN [--cells KEY ...] [--seeds SEEDS]``
    (the runs the ledger keeps of ``design``'s cells ``cells``, a key or shell-style pattern
    each, none: every cell; of their seeds, those of ``seeds``, None: every one;
    :func:`docking.study.design.cell_runs`). E.g. ``verify_command("bracketing-replication",
    "floor/paper", range(7100, 7105))`` is ``python -m docking verify --design
    bracketing-replication --cells floor/paper --seeds 7100-7104``. Its first line says how
    many runs and about how long (the ledger's wall times). Each word is quoted for a POSIX
    shell where it needs it (a pattern's ``*``). Whether the design has those cells and seeds
    is checked when the command runs: ``ValueError`` here only for what no command could
    name (an empty name, a seed that is no integer >= 0, no seeds)."""
    import shlex

    from docking.study.sweep import seeds_text
    from docking.validate import MAX_SEED, check_int, check_name

    check_name("verify_command", "design", design)
    cells = (cells,) if isinstance(cells, str) else tuple(cells)
    for k, cell in enumerate(cells):
        if not isinstance(cell, str) or not cell.strip() or not cell.isprintable():
            raise ValueError(
                f"verify_command.cells[{k}] must be a cell's key or pattern, got {cell!r}"
            )
    words = [*VERIFY.split(), "--design", design]
    if cells:
        words += ["--cells", *cells]
    if seeds is not None:
        if isinstance(seeds, str | bytes):
            raise TypeError(f"verify_command.seeds must be integers, got {seeds!r}")
        found = sorted(
            {check_int("verify_command", "seeds[]", s, lo=0, hi=MAX_SEED) for s in seeds}
        )
        if not found:
            raise ValueError("verify_command.seeds is empty: give None for every seed")
        words += ["--seeds", seeds_text(found).replace(" ", "")]
    return " ".join(shlex.quote(w) for w in words)
