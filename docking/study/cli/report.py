"""``report`` and ``figures``: the README's tables, summary, verdicts and first screen from
the designs' reports (each design's beside it, ``docking/study/designs/<design>_report.py``),
and the paper's figures, from runs the store or the ledger holds.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Annotated

from docking.study import paths
from docking.study.cli.options import (
    _absent,
    _FiguresDir,
    _Processes,
    _ResultsDir,
    _seed_text,
    _shown,
)


@dataclasses.dataclass
class Report:
    """Print the results: the paper's numbers beside ours, Experiment 3's table, the third
    edition's contest and verdict table, and the summary above them, from the runs the
    results store or the committed ledger holds (--compute: computing any that neither
    holds; without it, the report refuses to compute)."""

    readme: Annotated[Path | None, _shown("PATH", "none, the tables are only printed")] = None
    """Also write the table into this README, between <!-- results:start --> and
    <!-- results:end -->."""
    processes: _Processes = None
    """Worker processes for missing runs."""
    results_dir: _ResultsDir = None
    """The results store."""
    experiment3: bool = True
    """Also the table of Experiment 3 (notebook 06; runs it if it is not stored, and the
    oracle in every cell), into the README between <!-- experiment3:start --> and
    <!-- experiment3:end -->."""
    third_edition: bool = True
    """Also the third edition (notebooks 07 and 10): its contest in the README's summary and
    its table between <!-- third-edition:start --> and <!-- third-edition:end -->, its verdict
    table between <!-- verdicts:start --> and <!-- verdicts:end -->."""
    figures: bool = False
    """Also save the figures: the README's (its first screen's, the claims at a glance) and
    Figs. 2-5 and the learning curves of Experiments 1 and 2, into figures/ (or
    DOCKING_FIGURES, or --figures-dir). Without it (or --readme, which saves the README's),
    the report writes no file."""
    figures_dir: _FiguresDir = None
    """Save the figures (as --figures does) into this folder instead."""

    compute: bool = False
    """Compute the runs that neither the results store nor the ledger holds (without it, the
    report refuses to start a computation: Experiment 3 is hours on 2 cores)."""

    def execute(self) -> int:
        from docking.study import readme
        from docking.study.designs import (
            design,
            paper_report,
        )

        if not self.compute:
            _refuse_to_compute(self.experiment3, self.results_dir, self.third_edition)
        paper = design("paper").run(results_dir=self.results_dir, workers=self.processes)
        results = [paper.runs["experiment1"], paper.runs["experiment2"]]
        if self.figures or self.figures_dir is not None:
            save_paper_figures(*results, self.figures_dir)
        changed = self._write(paper_report.results_table(*results))
        comparisons, first = None, None
        if self.experiment3:
            comparisons, rates, text = self._experiment3()
            changed |= self._write(
                text, readme.EXPERIMENT3_START, readme.EXPERIMENT3_END, page=readme.FINDINGS_PAGE
            )
            first = rates[comparisons[0].four_key]
        contest, claims, untested, decisions, added = None, None, [], None, None
        if self.third_edition:
            contest, claims, untested, decisions, changed_here = self._third_edition()
            changed |= changed_here
            added = self._addendum()
        summary = self._details(results, comparisons, first, contest, claims, added, untested)
        changed |= self._write(
            summary, readme.DETAILS_START, readme.DETAILS_END, page=readme.FINDINGS_PAGE
        )
        if contest is not None:
            changed |= self._answer(results, comparisons, first, contest, decisions)
        if self.readme is not None:
            changed |= _write_timings(self.readme)
            print(f"{self.readme}: {'updated' if changed else 'already up to date'}")
        return 0

    def _save_figure(self, make, name: str) -> str:
        """The file name of the README's figure ``name`` (``.png``), which the README links
        in the figures folder; the figure (``make()``) is saved only if asked: with
        --readme, --figures or --figures-dir (into that folder). A report without them
        writes no file."""
        from docking.study import report

        if self.readme is None and not self.figures and self.figures_dir is None:
            return f"{name}.png"
        return Path(report.save_named(make(), name, self.figures_dir)).name

    def _details(self, results, comparisons, first, contest, claims, added, untested) -> str:
        """The findings page's detailed summary: what was reproduced, Experiment 3, the
        contest and its claims, the addendum and the bracketing, the untested claims and
        their revisit (kept for the first screen), and the study's provenance."""
        from docking.study import provenance, readme
        from docking.study.designs import (
            addendum_report,
            bracketing_report,
            revisited_report,
            untested_report,
        )

        summary = readme.summary_text(
            *results, comparisons, first, contest, claims, corrected=added is not None
        )
        if added is not None:
            from docking.study.designs import addendum

            unmerged = getattr(self, "_unmerged", None) or added  # the addendum as it ran
            summary += "\n\n" + addendum_report.addendum_summary(unmerged, contest, addendum)
            if getattr(self, "_bracketing", None):
                summary += "\n\n" + bracketing_report.bracketing_summary(
                    self._bracketing, added, addendum
                )
        for found, _ in untested:
            if found.design.name == "untested":
                summary += "\n\n" + untested_report.untested_summary(found)
            else:
                from docking.study.designs import revisited

                views = revisited.changed_views()  # rendered here, the report takes them
                self._revisited = revisited_report.revisited_rows(found, revisited, views)
                summary += "\n\n" + revisited_report.revisited_summary(
                    self._revisited, found, revisited
                )
        if self.third_edition:
            from docking.study import answer

            summary += "\n\n" + provenance.candour_text()
            summary += "\n\n" + answer.recompute_text()
        return summary

    def _write(self, text: str, *markers: str, page: str | None = None) -> bool:
        """Print ``text`` and write it into the README between ``markers`` (default: the
        results table's), or into the site's ``page`` beside it (a path relative to the
        README's folder, written where it exists); whether the file changed."""
        from docking.study.readme import update_readme

        print(text)
        if self.readme is None:
            return False
        target = self.readme if page is None else self.readme.parent / page
        return target.exists() and update_readme(target, text, *markers)

    def _experiment3(self) -> tuple:
        """Experiment 3's four-against-six comparisons, the oracle's rates and its table."""
        from docking.study.designs import experiment3, experiment3_report

        found = experiment3.run(results_dir=self.results_dir, workers=self.processes)
        oracle = experiment3.ORACLE.run(results_dir=self.results_dir, workers=self.processes)
        comparisons, rates = (
            experiment3_report.turning_comparisons(found),
            experiment3_report.oracle_rates(oracle),
        )
        return comparisons, rates, experiment3_report.turning_table(comparisons, rates)

    def _third_edition(self) -> tuple:
        """The third edition's contest table and verdict table (with the untested claims'
        rows, :meth:`_untested`) written; its results, its claims' sentence, the untested
        rows and whether the README changed."""
        from docking.study import readme
        from docking.study.claims import design_verdicts, judge_family
        from docking.study.designs import third_edition, third_edition_report

        contest = third_edition.DESIGN.run(results_dir=self.results_dir, workers=self.processes)
        untested = self._untested()
        changed = self._write(
            third_edition_report.contest_table(contest, third_edition_report.CONTEST_WORLDS),
            readme.THIRD_EDITION_START,
            readme.THIRD_EDITION_END,
            page=readme.FINDINGS_PAGE,
        )
        changed |= self._verdicts(
            design_verdicts(contest, *untested, notes=third_edition_report.OUTSIDE_COUNTS),
            third_edition_report.claims_glance_rows(
                contest, *untested, notes=third_edition_report.OUTSIDE_COUNTS
            ),
        )
        design = contest.design
        decisions = judge_family(design.claims, contest, alpha=design.alpha, per_claim=True)
        claims = third_edition_report.claims_summary(design.claims, decisions)
        return contest, claims, untested, decisions, changed

    def _verdicts(self, table: str, rows: list) -> bool:
        """The full verdict table into the site's page beside the README
        (:data:`docking.study.readme.VERDICTS_PAGE`, where it exists), and into the README the
        claims at a glance (its figure, saved into the figures folder) with a link to the
        page; whether either file changed."""
        from docking.study import figures, readme
        from docking.study.readme import update_readme

        print(table)
        png = self._save_figure(lambda: figures.fig_claims(rows), readme.CLAIMS_FIGURE)
        text = (
            f"\n![The paper's claims at a glance](figures/{png}) **The paper's claims at a "
            "glance:** one row per claim, one box per comparison (its world or setting, its 95% "
            "interval, its decision by the committed rule), coloured by the decision (green "
            "supported, red contradicted, orange at the bound, grey not supported; pale: outside "
            "the counts). The full verdict table, with the paper's words, every p-value and the "
            f"verdicts under both decision rules, is [a page of its own]({readme.VERDICTS_PAGE}).\n"
        )
        changed = self._write(text, readme.VERDICTS_START, readme.VERDICTS_END)
        if self.readme is not None:
            page = self.readme.parent / readme.VERDICTS_PAGE
            if page.exists():
                changed |= update_readme(page, table, readme.VERDICTS_START, readme.VERDICTS_END)
        return changed

    def _addendum(self):
        """The third edition's addendum's results, once every run of it is stored or in the
        ledger (None before), with the bracketing's tuned learners in place once its runs
        are in (:func:`docking.study.designs.bracketing_report.bracketed_addendum`; its rows kept
        for the first screen)."""
        from docking.study.design import absent_runs
        from docking.study.designs import addendum, bracketing_report

        if absent_runs(addendum.DESIGN, self.results_dir):
            return None
        added = addendum.DESIGN.run(results_dir=self.results_dir, workers=self.processes)
        from docking.study.designs import bracketing, bracketing_continued

        walk = None  # the last of the bracketing's designs whose every run is in
        for module in (bracketing, bracketing_continued):
            if not absent_runs(module.DESIGN, self.results_dir):
                walk = module
        if walk is None:
            return added
        own = walk.DESIGN.run(results_dir=self.results_dir, workers=self.processes)
        self._bracketing = bracketing_report.bracketing_rows(own, walk)
        self._unmerged = added
        return bracketing_report.bracketed_addendum(added, own, walk)

    def _answer(self, results, comparisons, oracle, contest, decisions) -> bool:
        """The README's first screen (:func:`docking.study.answer.equal_first_screen`, under
        the equal contest's glance figure, saved into the figures folder) and its summary,
        what the runs show in a few paragraphs, each number of the first screen among them;
        whether the README changed. The equal contest's, the replication's and the revisit's
        runs are read from the store or the ledger."""
        import numpy as np

        from docking.study import answer, figures, readme
        from docking.study.claims import rate_interval
        from docking.study.designs import equal_contest as ec
        from docking.study.designs import equal_contest_report as ecr
        from docking.study.designs import replication as rp
        from docking.study.designs import revisited
        from docking.study.designs.third_edition_report import claim_groups

        # read, never computed: a missing run of the published answer is an error, not hours
        # of computing started unasked (python -m docking design run NAME computes them)
        equal, second = ec.DESIGN.read(self.results_dir), rp.DESIGN.read(self.results_dir)
        verdicts = ecr.verdicts(equal)
        published = {w: rate_interval(contest, f"{w}/paper").estimate for w in ec.WORLDS}
        relocation = _relocation(revisited.DESIGN.read(self.results_dir), revisited)
        groups = claim_groups(contest.design.claims, decisions)
        png = self._save_figure(
            lambda: figures.fig_glance(*ecr.glance_data(equal, contest)), readme.GLANCE_FIGURE
        )
        text = answer.equal_first_screen(
            published,
            ecr.chosen(equal),
            ec.SEARCH.runs_per_learner(),
            verdicts,
            relocation,
            groups,
        )
        image = f"![The answer per world](figures/{png}) {ecr.GLANCE_CAPTION}"
        changed = self._write(f"\n{image}\n\n{text}\n", readme.GLANCE_START, readme.GLANCE_END)
        before = {
            w: float(np.mean(second.score(f"{w}/linear") - second.score(f"{w}/paper")))
            for w in rp.WORLDS
        }
        fragile = ecr.fragility(equal)
        summary = _summary(
            results,
            comparisons,
            oracle,
            (equal, verdicts, before, published, fragile),
            relocation,
            contest,
            decisions,
        )
        changed |= self._write(summary, readme.SUMMARY_START, readme.SUMMARY_END)
        detail = _equal_detail(equal, verdicts, before, published, fragile)
        return changed | self._write(
            detail, readme.EQUAL_START, readme.EQUAL_END, page=readme.FINDINGS_PAGE
        )

    def _untested(self) -> list:
        """The untested claims' rows of the verdict table
        (:data:`docking.study.designs.untested_report.UNTESTED_IN_README`) and their revisit's
        (:data:`docking.study.designs.revisited_report.REVISITED_IN_README`), each once every run of
        its design (``untested.part("judged")``, ``revisited.DESIGN``) is stored or in the
        ledger."""
        from docking.study.design import absent_runs
        from docking.study.designs import revisited, untested
        from docking.study.designs.revisited_report import REVISITED_IN_README
        from docking.study.designs.untested_report import UNTESTED_IN_README

        found = []
        for design, keys in (
            (untested.part("judged"), UNTESTED_IN_README),
            (revisited.DESIGN, REVISITED_IN_README),
        ):
            if not absent_runs(design, self.results_dir):
                runs = design.run(results_dir=self.results_dir, workers=self.processes)
                found.append((runs, keys))
        return found


def _summary(results, comparisons, oracle, equal_parts, relocation, contest, decisions) -> str:
    """The README's summary: what was reproduced, the equal contest (its verdict table; the
    chosen settings are on the findings page), its fragility sentence, relocation, the claims
    and turning, each paragraph's numbers from the runs."""
    from docking.study import answer, readme
    from docking.study.designs import equal_contest_report as ecr

    equal, verdicts, before, published, fragile = equal_parts
    paragraphs = [
        readme.reproduced_text(*results),
        answer.equal_text(
            ecr.verdict_table(equal),
            ecr.chosen_sentence(ecr.chosen(equal))
            + " The runs each spent, and the selection's optimism: "
            "[the findings page](docs/guide/findings.md).",
            verdicts,
            before,
            published,
        ),
        "**The fragility landscape** (beyond the paper, notebook 07). "
        + ecr.fragility_sentence(fragile),
        answer.relocation_text(relocation),
        answer.claims_text(_claim_counts(contest, decisions)),
    ]
    if comparisons:
        paragraphs.append(readme.turning_text(comparisons, oracle))
    paragraphs.append(
        f"Every number of the study, with its interval, its rule and its notebook: [what the "
        f"runs show, in detail]({readme.FINDINGS_PAGE})."
    )
    return "\n\n".join(paragraphs)


def _equal_detail(equal, verdicts, before, published, fragile) -> str:
    """The findings page's section on the equal contest: its paragraph and tables (links to the
    glossary beside the page) and its fragility tables."""
    from docking.study import answer, provenance
    from docking.study.designs import equal_contest as ec
    from docking.study.designs import equal_contest_report as ecr

    text = answer.equal_text(
        ecr.verdict_table(equal),
        "What each learner chose, the runs it spent, and its success on the grid's seeds, the "
        "selection seeds and the judged seeds (a fall is the selection's optimism):\n\n"
        + ecr.chosen_table(equal),
        verdicts,
        before,
        published,
        glossary="glossary.md",
    )
    deviations = "**Its deviation from its rules** (notebook 07):\n\n" + (
        provenance.deviations_table(ec.NAME)
    )
    text += "\n\n" + deviations
    fragility = (
        "**Fragility on the common grid** (notebook 07). "
        + ecr.fragility_sentence(fragile)
        + "\n\n"
        + ecr.fragility_table(fragile)
    )
    return text + "\n\n" + fragility


def _claim_counts(contest, decisions) -> tuple[int, int, int, int, int]:
    """The paper's claims' counts (:func:`docking.study.answer.claims_text`): judged, held and
    contradicted under the committed rule, then as one family."""
    from docking.study.claims import judge_family
    from docking.study.designs.third_edition_report import claim_groups

    design = contest.design
    per_claim, family = (
        claim_groups(design.claims, rule)
        for rule in (decisions, judge_family(design.claims, contest, alpha=design.alpha))
    )
    return (sum(len(v) for v in per_claim.values()), *_held(per_claim), *_held(family))


def _held(groups: dict) -> tuple[int, int]:
    """Of the claims grouped by their verdicts (``claim_groups``): how many hold in at least
    one world, and how many are contradicted in at least one."""
    held = ("supported wherever judged", "supported in some worlds only")
    return (
        sum(len(groups.get(g, [])) for g in held),
        len(groups.get("contradicted in at least one world", [])),
    )


def _relocation(results, rv) -> dict:
    """Relocation as measured, for the first screen: the revisit's report
    (:func:`docking.study.designs.revisited_report.relocation`) of ``results`` of ``rv``, with
    the landmark's shift in the start views at each camera height rendered here
    (:func:`docking.study.analysis.view_shift`)."""
    from docking.study.analysis import view_shift
    from docking.study.designs.revisited_report import relocation

    places = rv.places()
    shifts = {p: view_shift(rv._HOME, places[p]) for p in ("sideboard higher", "sideboard lower")}
    return relocation(results, rv, shifts)


def _write_timings(readme: Path) -> bool:
    """The README's paragraph of times from the ledger (its runs' wall times and the tiers'
    record of tools/time_tiers.py); whether the README changed."""
    from docking.study import ledger
    from docking.study.readme import TIMINGS_END, TIMINGS_START, timings_text, update_readme

    data = ledger.manifest()
    if data is None:
        return False
    walls = sum(r["wall_seconds"] for r in data["runs"].values())
    text = timings_text(
        ledger.timings(), len(data["runs"]), walls, ledger_bytes=ledger.size_bytes()
    )
    return update_readme(readme, text, TIMINGS_START, TIMINGS_END)


def _refuse_to_compute(experiment3: bool, results_dir, third_edition: bool = False) -> None:
    """``ValueError`` if the report would compute runs: it names how many and the option."""
    from docking.study.design import absent_runs
    from docking.study.designs import design
    from docking.study.designs import third_edition as te

    names = ["paper"] + ["experiment3", "experiment3-oracle"] * experiment3
    designs = [design(name) for name in names] + [te.DESIGN] * third_edition
    absent = [job for d in designs for job in absent_runs(d, results_dir)]
    if absent:
        kinds = sorted({j.config.name for j in absent})
        text = f"{len(absent)} runs ({', '.join(kinds)}) are neither stored nor in the ledger"
        how = (
            "pass --compute to compute them (from minutes to hours), or run the designs first "
            "(python -m docking design run ...)"
        )
        raise ValueError(_absent(text, how))


@dataclasses.dataclass
class Figures:
    """Regenerate Figs. 2-5 and the learning curves of Experiments 1 and 2 from their runs in
    the results store or the committed ledger (never computing one); Experiment 3's figures
    are written by notebook 06, the study's by notebooks 07 and 08."""

    folder: _FiguresDir = None
    """Where the .png and .pdf files go."""
    results_dir: _ResultsDir = None
    """The results store."""

    def execute(self) -> int:
        from docking.presets import EXPERIMENT_1, EXPERIMENT_2, SEEDS
        from docking.study.runs import load_run

        results = []
        for config in (EXPERIMENT_1, EXPERIMENT_2):
            runs = [load_run(config, s, self.results_dir) for s in SEEDS[config.name]]
            absent = [s for s, r in zip(SEEDS[config.name], runs, strict=True) if r is None]
            if absent:
                text = (
                    f"{config.name} seeds {_seed_text(absent)} are neither stored nor in the ledger"
                )
                how = f"compute them with python -m docking run {config.name}"
                raise ValueError(_absent(text, how))
            results.append(runs)
        for fig in save_paper_figures(*results, self.folder):
            del fig
        print(f"figures written to {self.folder or paths.figures_dir()}")
        return 0


def save_paper_figures(results1, results2, folder=None) -> list:
    """Every figure of the paper's design, from the runs of Experiments 1 and 2 (``results1``,
    ``results2``) and the world (this caller renders; the report takes arrays): Fig. 2 (the
    default world), Fig. 3 (the headline run of ``results1``), Figs. 4 and 5 (the headline
    run of ``results2``) and the learning curves, saved in ``folder`` (default
    :data:`docking.study.figures.FIGURES_DIR`)."""
    from docking.study import analysis
    from docking.study.designs import paper_report as pr
    from docking.world import DockingEnv

    main1, main2 = pr.headline(results1), pr.headline(results2)
    env = DockingEnv(seed=0)
    views = analysis.example_views(env)
    world2 = main2.config.world
    inputs = analysis.mean_winning_inputs(main2.network, world2, n=1500)
    return [
        pr.save_fig2(env.config.camera, views, analysis.overview(env, views.poses[1]), folder),
        pr.save_fig3(main1, analysis.example_views(DockingEnv(main1.config.world, seed=0)), folder),
        pr.save_fig4(main2, inputs, analysis.start_fields(main2), folder),
        pr.save_fig5(main2, analysis.floor_plan(world2), folder),
        pr.save_learning_curves(results1, results2, folder),
    ]
