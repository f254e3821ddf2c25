"""The report of relocation and coping revisited (:mod:`docking.study.designs.revisited`,
notebook 09): its rows, its claims that join the README's verdicts, and its sentence.
"""

from __future__ import annotations

import numpy as np

from docking.study.designs.third_edition_report import claims_summary
from docking.study.report import _pct

#: The claims of their revisit (:mod:`docking.study.designs.revisited`) that join it.
REVISITED_IN_README = ("relocation-height", "coping-early")


def revisited_rows(results, rv, views: dict[str, tuple[int, int]]) -> dict:
    """What the revisit of relocation and coping (``results`` of ``rv``:
    :mod:`docking.study.designs.revisited`) measured, for its sentences and notebook 09: per
    place, the start views it changes (``views``: ``{place: (changed, n)}``, rendered by the
    caller, :func:`docking.study.designs.revisited.changed_views`) and the home networks'
    held-out success there and at home; per change, each arm's early failure (mean over
    seeds) and the sign test of trials to regain (``(sooner, signed pairs, p)``); and the
    decisions (Holm within each claim)."""
    from docking.study.claims import judge_family, rate_interval

    design = results.design
    decisions = judge_family(design.claims, results, alpha=design.alpha, per_claim=True)
    places = {
        place: dict(
            views=views[place],
            home=rate_interval(results, "home/paper"),
            there=rate_interval(results, f"{place}/paper"),
            oracle=rate_interval(results, f"{place}/oracle"),
        )
        for place in rv.places()
    }
    changes = {}
    for change in rv.untested.CHANGES:
        relearn, fresh = f"{change}/paper-relearn", f"{change}/paper-fresh"
        changes[change] = dict(
            relearn=float(np.mean(rv.early_failure(results, relearn))),
            fresh=float(np.mean(rv.early_failure(results, fresh))),
            regain=rv.regain_sign_test(
                rv.regain_trials(results, relearn, "home/paper"),
                rv.regain_trials(results, fresh, "home/paper"),
            ),
        )
    verdict = {(d.claim, d.world): d.verdict for d in decisions}
    return dict(
        places=places,
        changes=changes,
        verdict=verdict,
        decisions=decisions,
        height=rv.HEIGHT_CHANGE,
    )


def revisited_summary(rows: dict, results, rv) -> str:
    """The README's paragraph on relocation and coping revisited (``rows``:
    :func:`revisited_rows` of ``results`` of ``rv``)."""
    design = results.design

    def gain(r) -> str:  # the equivalence rule is two-sided: a gain counts too
        if r["there"].estimate <= r["home"].estimate:
            return ""
        return ", docking more often than at home, which the two-sided rule counts too"

    place_text = "; ".join(
        f"{p}: {r['views'][0]} of {r['views'][1]} start views changed, "
        f"{r['there'].format(unit='%')} against {r['home'].format(unit='%')} at home "
        f"({rows['verdict']['relocation-height', p]}{gain(r)})"
        for p, r in rows["places"].items()
    )
    change_text = "; ".join(
        f"{c}: {_pct(r['relearn'])} against {_pct(r['fresh'])} "
        f"({rows['verdict']['coping-early', c]}; sooner to regain {rv.REGAIN:.0%} of home "
        f"success in {r['regain'][0]} of {r['regain'][1]} pairs with a sign, sign test "
        f"p {r['regain'][2]:.2g})"
        for c, r in rows["changes"].items()
    )
    return (
        "**Relocation and coping, revisited** (notebook 09: tests that can fail, rules "
        "committed before the runs, fresh seeds). *Relocation*, with the landmark "
        f"{100 * rv.HEIGHT_CHANGE:.0f} cm lower or higher (the home networks' held-out "
        f"success, within +-{100 * rv.RELOCATION_MARGIN:.0f} pp of home to be supported): "
        f"{place_text}. *Coping*, the share of failed greedy trials over the first "
        f"{rv.EARLY_TRIALS} training trials after a change, the home network learning on "
        f"against a fresh network: {change_text}. "
        + claims_summary(design.claims, rows["decisions"], design.alpha)
    )


def relocation(results, rv, shifts: dict[str, np.ndarray]) -> dict:
    """Relocation as measured, for the first screen (``results`` of the revisit ``rv``): a
    camera-height change in the sideboard world, the camera ``rv.HEIGHT_CHANGE`` lower or
    higher (the places ``sideboard higher`` and ``sideboard lower``: the landmark as if that
    much higher or lower); the mean shift of the landmark in the start views in input rows at
    each height, with its sign (up negative; ``shifts``: per place, each start view's shift,
    :func:`docking.study.analysis.view_shift`, rendered by the caller), and each learner's
    held-out success at home and at each height over the revisit's seeds, and the verdicts."""
    from docking.study.claims import judge_family, rate_interval

    found = dict(cm=100 * rv.HEIGHT_CHANGE, world="sideboard", seeds=len(rv.SEEDS))
    found["shift lower"] = float(np.mean(shifts["sideboard higher"]))
    found["shift higher"] = float(np.mean(shifts["sideboard lower"]))
    found["shift"] = float(np.mean([abs(found["shift lower"]), abs(found["shift higher"])]))
    names = {"sideboard higher": "camera lower", "sideboard lower": "camera higher"}
    for learner, prefix in (("paper", ""), ("linear", "linear ")):
        found[prefix + "home"] = rate_interval(results, f"home/{learner}").estimate
        for place, name in names.items():
            found[prefix + name] = rate_interval(results, f"{place}/{learner}").estimate
    design = results.design
    for d in judge_family(design.claims, results, alpha=design.alpha, per_claim=True):
        if d.claim == "relocation-height":
            found[f"verdict {names[d.world]}"] = d.verdict
    return found
