"""The cost ladder: errors against the reference, recommendation, bad input."""

import numpy as np
import pytest

from fretwear import paper_model
from fretwear.accuracy import CostStudy, Rung, cost_ladder


def test_ladder_errors_fall_with_harmonics_and_the_recommendation_is_the_cheapest():
    study = cost_ladder(paper_model(fex=10), 0.9, harmonics=(3, 21, 81), sample_factors=())
    dlft = {r.settings["Nh"]: r for r in study.rungs if r.method == "dlft"}
    assert dlft[81].error("x1_h1") < dlft[21].error("x1_h1") < dlft[3].error("x1_h1")
    assert study.rungs[0].method == "shooting" and study.rungs[0].error() == 0
    assert "shooting" in study.reference["periodic"]
    pick = study.recommend(0.1)
    assert pick is not None and pick.error() <= 0.1
    assert all(r.wall_time >= pick.wall_time for r in study.rungs if r.converged and r.error() <= 0.1)
    front = study.pareto()
    assert [r.wall_time for r in front] == sorted(r.wall_time for r in front)
    assert all(a.error() > b.error() for a, b in zip(front, front[1:], strict=False))


def test_recommend_none_and_bad_target():
    study = CostStudy(1.0, [Rung("dlft", {"Nh": 1}, 1e-3, {"x1_h1": 0.5})], {"periodic": "test"})
    assert study.recommend(1e-3) is None
    with pytest.raises(ValueError, match="target"):
        study.recommend(0.0)


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
