"""The numbers of the README and of the docs pages its text moved to (docs/guide.md, docs/models.md,
docs/scenes.md) that a committed report measured are read from that report: a test fails when they drift.

Each claim names the page, the report, the quantity (read from its results.json, as the study computed it) and
the text the page states it in. Regenerating a report that moves a number fails this test until the page says
the new one: a number is never typed twice.
"""

import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
GUIDE, MODELS, SCENES = (ROOT / "docs" / f"{page}.md" for page in ("guide", "models", "scenes"))


def results(study: str) -> dict:
    return json.loads((ROOT / "reports" / study / "results.json").read_text())


def paper_fold_ratios() -> list[str]:
    """The paper study's fold wavelength of `paper` over `curtain-silky`, FD and FE (section 5, Fig. 6)."""
    ratio = results("paper")["data"]["folds"]["ratio"]
    return [f"measured {ratio['fd']:.2f} times on FD", f"and {ratio['fe']:.2f} on FE"]


def mesh_ridge_friction() -> list[str]:
    """The contact study's effective friction coefficients over a mesh edge in the flat (FD, FE), as its
    finding computes them from the measured accelerations."""
    finding = next(f for f in results("contact")["findings"] if "effective friction coefficient of" in f)
    fd, fe = (float(v) for v in re.search(r"effective friction coefficient of ([\d.]+), ([\d.]+)", finding).groups())
    return [f"an effective friction coefficient of {fd:.3f} on FD and {fe:.3f} on FE"]


def late_drape_spread() -> list[str]:
    """The contact study's late drape: how far the ball's triangulations (levels 3, 4) moved it (cm)."""
    late = results("contact")["data"]["mesh_ball_late"]
    moved = [v["largest"] for k, v in late.items() if k.startswith("level")]
    assert len(moved) == 2, moved
    return [f"triangulation (levels 3 and 4) by {100 * min(moved):.0f}-{100 * max(moved):.0f} cm"]


def quick_checks() -> list[str]:
    """The quick report's count of checks, every one of them passed (the README's quick start)."""
    studies = ["tensors", "modes", "statics", "time", "compatibility", "work", "variational", "fabrics"]
    passed = sum(results(s)["passed"] for s in studies)
    failed = sum(results(s)["failed"] for s in studies)
    return [f"{passed} of {passed + failed} checks"]


def fabrics_peirce() -> list[str]:
    """The fabrics study's largest error of a measured bending length against its source's, FD and FE (%)."""
    data = results("fabrics")["data"]
    fd, fe = (100 * max(abs(r["relative_error"]) for r in data[b]) for b in ("fd", "fe"))
    return [f"within {fd:.2f} % of the sources' on FD and {fe:.2f} % on FE"]


#: each claim and the page that states it
CLAIMS = [(SCENES, paper_fold_ratios), (SCENES, mesh_ridge_friction), (SCENES, late_drape_spread),
          (README, quick_checks), (MODELS, fabrics_peirce)]


@pytest.mark.parametrize("page, claim", CLAIMS, ids=[c.__name__ for _, c in CLAIMS])
def test_the_page_states_the_number_its_report_measured(page, claim):
    text = " ".join(page.read_text().split())  # lines folded as Markdown folds them
    for phrase in claim():
        where = page.relative_to(ROOT)
        assert phrase in text, f"{where} does not say {phrase!r} ({claim.__doc__.split(':')[0].strip()})"


def test_the_params_output_the_guide_quotes_is_what_the_tool_prints(capsys):
    """The user guide's `deformable params curtain scale=20` sentence: the scaled sheet's equivalent eta and xi as
    printed."""
    from validation.commands import main

    assert main(["params", "curtain", "scale=20"]) == 0
    printed = re.search(r"moves as the real one would with (eta = \S+ N/m) and (xi = \S+ N m)", capsys.readouterr().out)
    assert printed, "deformable params curtain scale=20 no longer says what scale does"
    eta, xi = printed.groups()
    eta_value = eta.split("= ")[1].split(" ")[0]
    text = " ".join(GUIDE.read_text().split())
    assert f"move as the real sheet would with eta = {eta_value} N/m and {xi}" in text

