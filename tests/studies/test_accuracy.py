"""The cost ladder: errors against the reference, recommendation, bad input."""

import numpy as np
import pytest

from fretwear import paper_model
from fretwear.studies.accuracy import CostStudy, Rung, cost_ladder


def test_ladder_errors_fall_with_harmonics_and_the_recommendation_is_the_cheapest():
    study = cost_ladder(paper_model(fex=10), 0.9, harmonics=(3, 21, 81), sample_factors=())
    dlft = {r.settings["Nh"]: r for r in study.rungs if r.method == "dlft"}
    assert dlft[81].error("x1_h1") < dlft[21].error("x1_h1") < dlft[3].error("x1_h1")
    # shooting is a rung measured against a tighter shooting solve, not its own reference
    assert study.rungs[0].method == "shooting" and 0 <= study.rungs[0].error() < 1e-8
    assert "shooting, tol 1e-12" in study.reference["periodic"]
    pick = study.recommend(0.1)
    assert pick is not None and pick.error() <= 0.1
    assert not pick.reference and study.rungs[0].reference
    assert all(r.wall_time >= pick.wall_time for r in study.rungs[1:] if r.converged and r.error() <= 0.1)
    front = study.pareto()
    assert [r.wall_time for r in front] == sorted(r.wall_time for r in front)
    assert all(a.error() > b.error() for a, b in zip(front, front[1:], strict=False))


def test_recommend_none_and_bad_target():
    study = CostStudy(1.0, [Rung("dlft", {"Nh": 1}, 1e-3, {"x1_h1": 0.5})], {"periodic": "test"})
    assert study.recommend(1e-3) is None
    with pytest.raises(ValueError, match="target"):
        study.recommend(0.0)


def test_the_reference_is_never_the_recommendation():
    """The shooting rung is the reference's own method (error 0): the cheapest other rung within the
    target is recommended, and when none is, the summary says only the reference meets it."""
    zero = {"x1_h1": 0.0, "xr_half_p2p": 0.0, "sliding_distance": 0.0}
    ref = Rung("shooting", {}, 1e-4, zero, reference=True)
    dlft = Rung("dlft", {"Nh": 21}, 1e-2, {q: 0.005 for q in zero})
    study = CostStudy(1.0, [ref, dlft], {"periodic": "shooting, tol 1e-12"})
    assert study.recommend(0.01) is dlft
    assert study.summary(0.01).startswith("cheapest rung within 0.01: dlft Nh=21 (10.0 ms); the exact answer")
    assert study.recommend(1e-3) is None
    assert study.summary(1e-3).startswith("no approximation meets 0.001: only the reference does")


@pytest.mark.parametrize(
    "kwargs,match", [(dict(frequency=0.0), "frequency"), (dict(kw=1e-11), "kw and cycles")]
)
def test_bad_input(kwargs, match):
    args = dict(model=paper_model(), frequency=0.7)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        cost_ladder(**args)


def test_nan_free_errors():
    study = cost_ladder(paper_model(fex=10), 0.7, harmonics=(3,), sample_factors=(8,))
    assert all(np.isfinite(r.error()) for r in study.rungs)


def test_progress_and_the_exact_load_path_rungs():
    seen = []
    study = cost_ladder(
        paper_model(fex=10), 0.7, harmonics=(3,), sample_factors=(), kw=1e-11, cycles=1e3, tolerances=(1e-1,),
        degrees=(2,), wear_harmonics=(3,), include_time_integration=False, progress=seen.append,
    )  # fmt: skip
    assert [r.label.strip() for r in study.rungs] == [
        "shooting", "dlft Nh=3 N=64", "exact-dlft Nh=3", "stepping Nh=3 tol=0.1", "stepping-shooting tol=0.1",
        "polynomial Nh=3 degree=2",
    ]  # fmt: skip
    # one report per rung and one per reference (periodic, w(N))
    assert seen == sorted(seen) and seen[-1] == 1 and len(seen) == len(study.rungs) + 2
    assert all(np.isfinite(r.error("wear")) for r in study.rungs[2:])
    assert "exact dynamics" in study.reference["wear"]
    # with wear rungs, "within the target on everything" means on w(N): a periodic rung never answers it
    pick = study.recommend(0.5)
    assert pick is not None and np.isfinite(pick.error("wear")) and pick.error("wear") <= 0.5
    assert study.required() == ("wear",) and study.required("x1_h1") == ("x1_h1",)

    class Stop(Exception):
        pass

    def stop(fraction):
        if fraction > 0.5:
            raise Stop

    with pytest.raises(Stop):  # a caller's cancellation stops the ladder
        cost_ladder(paper_model(fex=10), 0.7, harmonics=(1, 3, 5), sample_factors=(), progress=stop)
