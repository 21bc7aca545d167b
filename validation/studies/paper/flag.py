r"""The flag (section 5, Figs 7-8): does it wave, and which way do its waves travel?

The paper's flag is driven by "a coil force on one side"; the shipped scene
(:func:`deformable.scenes.flag`) pins the pole edge a1 = 0, shakes the flag
next to the pole with two coils whose anchors swing across it at f = 6 Hz,
blows wind across its folds and pulls it out along the flow. A flag *waves* when the motion across it, y, is a
travelling wave: the phase of its driving-frequency component changes along
the flag. A flag that only flaps moves in phase everywhere.

The measure. Along the middle row (a2 = L2 / 2, pole to tip) y is recorded
every step. Over a window of whole periods after the coils' ramp, each
sample point's y(t) is fitted by least squares with ``c0 + c1 t + a cos(w t)
+ b sin(w t)``, w = 2 pi f (the constant and the drift take out the mean
position and its slow change); its driving component is ``R cos(w t - phi)``
with ``R = |a - i b|`` and the phase lag ``phi = -arg(a - i b)``. Along the
row, phi is unwrapped from the pole, over the points where R is at least
:data:`AMPLITUDE_FLOOR` of its largest value (near the pinned pole R falls to
zero and the phase is noise). For a wave ``cos(w t - k a1)``, phi = k a1: phi
increasing from pole to tip means a wave travelling towards the tip,
decreasing one travelling towards the pole. The phase change is the span of
phi between the first and last such points; the phase speed
``c = w / |d phi / d a1|``, the slope fitted by least squares (m/s of
material length along the flag); a flag flapping in phase has a phase change
near 0 and an unbounded phase speed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .analysis import classify
from .cases import scene_grids
from .claims import Claim, checks_of
from .pictures import panels_figure

__all__ = ["AMPLITUDE_FLOOR", "AMPLITUDE_TIP", "driving_component", "phase_along", "PhaseProfile", "window", "run_phase", "measure"]

#: sample points whose driving amplitude is below this fraction of the row's largest are left out of the phase
AMPLITUDE_FLOOR = 0.1
#: the waves' amplitude at the free edge, at least this fraction of the flag's length (issue 29)
AMPLITUDE_TIP = 0.1


@dataclass(frozen=True)
class PhaseProfile:
    """The driving component along a row.

    a : (P,) material coordinates (m); amplitude : (P,) R (m); phase : (P,) the unwrapped lag phi (rad, NaN
    where R is below the floor); change : phi(last) - phi(first) over the kept points (rad); speed : phase
    speed (m/s, inf when phi does not change); direction : "towards the tip", "towards the pole" or "none".
    """

    a: np.ndarray
    amplitude: np.ndarray
    phase: np.ndarray
    change: float
    speed: float
    direction: str


def driving_component(t, y, frequency: float) -> np.ndarray:
    """Complex amplitudes ``a - i b`` of the component at ``frequency`` (Hz) of y (T, P) sampled at t (T,).

    Least squares on ``c0 + c1 t + a cos(w t) + b sin(w t)`` for every column of y; so
    ``y ~ Re((a - i b) e^{i w t})`` plus the mean and drift.
    """
    t, y = np.asarray(t, float), np.asarray(y, float)
    if t.ndim != 1 or y.shape[0] != t.size or t.size < 5:
        raise ValueError(f"need at least 5 samples, y of shape (T, P) with T = len(t); got {y.shape}, {t.shape}")
    w = 2.0 * math.pi * frequency
    tc = t - t.mean()
    A = np.stack([np.ones_like(t), tc, np.cos(w * t), np.sin(w * t)], axis=1)
    coef, *_ = np.linalg.lstsq(A, y.reshape(t.size, -1), rcond=None)
    return coef[2] - 1j * coef[3]


def phase_along(a, t, y, frequency: float) -> PhaseProfile:
    """The driving component's amplitude and unwrapped phase lag along a row, its change and phase speed."""
    a = np.asarray(a, float)
    c = driving_component(t, y, frequency)
    R = np.abs(c)
    keep = R >= AMPLITUDE_FLOOR * R.max() if R.max() > 0 else np.zeros_like(R, bool)
    phase = np.full(a.shape, math.nan)
    if keep.sum() < 2:
        return PhaseProfile(a, R, phase, math.nan, math.nan, "none")
    idx = np.flatnonzero(keep)
    # unwrap over the kept points in order from the pole (points left out are skipped, not bridged with noise)
    phase[idx] = np.unwrap(-np.angle(c[idx]))
    change = float(phase[idx[-1]] - phase[idx[0]])
    slope = float(np.polyfit(a[idx], phase[idx], 1)[0])
    w = 2.0 * math.pi * frequency
    speed = w / abs(slope) if slope != 0 else math.inf
    direction = "towards the tip" if slope > 0 else "towards the pole" if slope < 0 else "none"
    return PhaseProfile(a, R, phase, change, speed, direction)


def window(t_end: float, ramp: float, frequency: float, settle: float = 0.5) -> tuple[float, float]:
    """The analysis window: the most whole periods that fit between ``ramp + settle`` and ``t_end`` (s)."""
    periods = math.floor((t_end - ramp - settle) * frequency + 1e-9)
    if periods < 1:
        raise ValueError(f"no whole period of {frequency:g} Hz between t = {ramp + settle:g} s and {t_end:g} s")
    return t_end - periods / frequency, t_end


def run_phase(r: dict, t_end: float) -> PhaseProfile | None:
    """The phase profile of a recorded flag run over the window of a run to ``t_end`` (s); None when the run
    stopped before it ended (diverged or stalled: no window to fit)."""
    t = np.asarray(r["line_t"])
    if r["status"] != "finished" or t.size == 0:
        return None
    cfg = r["config"]
    lo, hi = window(t_end, cfg["ramp"], cfg["frequency"])
    if t[-1] < hi - 1e-9:
        return None
    sel = (t >= lo - 1e-9) & (t <= hi + 1e-9)
    return phase_along(r["a"], t[sel], np.asarray(r["line"])[sel], cfg["frequency"])


def measure(res, R: dict, s: dict) -> list:
    """Section 5 (Figs 7-8): the phase of the driving component along the flag, both backends and force models.

    Checks (the shipped flag, energy-consistent model, both backends): a travelling wave, the phase changing
    by more than pi from pole to tip; travelling from the pole to the free edge (the phase lag increasing
    along the flag), as a real flag's waves do; its amplitude at the free edge at least :data:`AMPLITUDE_TIP`
    of the flag's length (Figs 7-8's large waves). Reported: the phase speed; the paper's force as a finding.
    """
    from validation.harness.backends import BACKENDS
    from validation.harness.study import Figure, Table


    n = dict(zip(BACKENDS, scene_grids(s, "flag")))
    P, rows = {}, []
    for b in BACKENDS:
        for fm in ("variational", "tpbf87"):
            r = R[("flag", b, fm)]
            p = P[(b, fm)] = run_phase(r, s["s5_t"])
            grid = f"{n[b]}x{n[b]} nodes" if b == "fd" else f"{n[b] - 1}x{n[b] - 1} el."
            rows.append((b.upper(), grid, fm, classify(r), r["t"],
                         p.change if p else math.nan, p.speed if p else math.nan, p.direction if p else "not measured",
                         float(np.nanmax(p.amplitude)) if p else math.nan))
    cfg = R[("flag", "fd", "variational")]["config"]
    lo, hi = window(s["s5_t"], cfg["ramp"], cfg["frequency"])
    res.tables.append(Table(
        "flag", "Section 5 (Figs 7-8): the flag's wave, phase of the driving component along the middle row",
        ("backend", "grid", "force model", "class", "t reached (s)", "phase change pole to tip (rad)",
         "phase speed (m/s)", "wave travels", "largest amplitude (m)"), rows,
        note=f"The shipped flag (deformable.scenes.flag: coils swinging at {cfg['frequency']:g} Hz beside the pole, "
             f"wind and the flow's pull along the flag), y along a2 = L2 / 2 fitted over t = {lo:g} .. {hi:g} s with c0 + c1 t + a cos(w t) "
             "+ b sin(w t) at each point; phase lag unwrapped from the pole over the points with at least "
             f"{AMPLITUDE_FLOOR:.0%} of the largest amplitude; phase speed w / |d phi / d a1| (m/s along the flag; "
             "module docstring of validation.studies.paper.flag)."))
    res.check_all("section 5, flag: a travelling wave on both backends",
                  "the driving component's phase changes by more than pi from pole to tip (energy-consistent model)",
                  {f"{b.upper()} ({abs(P[(b, 'variational')].change):.2f} rad)" if P[(b, "variational")] else
                   f"{b.upper()} (run did not finish)": bool(P[(b, "variational")]) and
                   abs(P[(b, "variational")].change) > math.pi for b in BACKENDS})
    res.check_all("section 5, flag: the waves travel from the pole to the free edge",
                  "the phase lag increases from pole to tip (a wave cos(w t - k a1), k > 0; energy-consistent model)",
                  {f"{b.upper()} ({P[(b, 'variational')].direction}, {P[(b, 'variational')].speed:.2f} m/s)"
                   if P[(b, "variational")] else f"{b.upper()} (run did not finish)":
                   bool(P[(b, "variational")]) and P[(b, "variational")].direction == "towards the tip"
                   for b in BACKENDS})
    length = cfg["size"][0]
    res.check_all(f"section 5, flag: waves at least {AMPLITUDE_TIP:g} of the flag's length at its free edge",
                  f"the driving component's amplitude at the tip >= {AMPLITUDE_TIP:g} L1 = {AMPLITUDE_TIP * length:g} m "
                  "(energy-consistent model)",
                  {f"{b.upper()} ({P[(b, 'variational')].amplitude[-1]:.3f} m)" if P[(b, "variational")] else
                   f"{b.upper()} (run did not finish)": bool(P[(b, "variational")]) and
                   P[(b, "variational")].amplitude[-1] >= AMPLITUDE_TIP * length for b in BACKENDS})
    res.data["flag"] = {f"{b}|{fm}": (dict(change=p.change, speed=p.speed, direction=p.direction,
                                          a=p.a, phase=p.phase, amplitude=p.amplitude) if p else None)
                        for (b, fm), p in P.items()}
    res.findings.append(
        "Section 5, flag: " + "; ".join(
            f"{b.upper()} {fm}: " + (f"phase change {p.change:+.2f} rad, phase speed {p.speed:.2f} m/s {p.direction}"
                                     if p else f"{classify(R[('flag', b, fm)])}, not measured")
            for (b, fm), p in P.items())
        + ". The coils shake the flag beside the pole and the flow's pull puts it in a tension that falls to nothing "
          "at the free edge: the waves travel from the pole to the free edge, slowing and growing on the way "
          "(deformable.scenes, 'flag').")
    style = {"fd": "tab:blue", "fe": "tab:orange"}
    phase_lines, amp_lines = [], []
    for (b, fm), p in P.items():
        if p is None:
            continue
        st = "-" if fm == "variational" else "--"
        phase_lines.append(dict(x=p.a, y=p.phase, style=st, color=style[b], label=f"{b.upper()} {fm}"))
        amp_lines.append(dict(x=p.a, y=p.amplitude, style=st, color=style[b], label=f"{b.upper()} {fm}"))
    res.figures.append(Figure("flag_phase", "Section 5: the flag's driving component along the middle row, pole (0) "
                              "to tip: phase lag (left; increasing towards the tip = a wave travelling towards the "
                              "tip) and amplitude (right)",
                              image=panels_figure([
                                  dict(title=f"phase lag of the {cfg['frequency']:g} Hz component", xlabel="a1 (m)",
                                       ylabel="phi (rad)", lines=phase_lines),
                                  dict(title="amplitude", xlabel="a1 (m)", ylabel="R (m)", lines=amp_lines)],
                                  "The flag's wave")))
    v = [P[(b, "variational")] for b in BACKENDS]
    paper = [P[(b, "tpbf87")] for b in BACKENDS]
    return [Claim("Figs 7-8: a coil force on one side makes the flag wave", "5",
                  "phase change " + ", ".join(f"{b.upper()} {p.change:+.2f} rad" if p else f"{b.upper()} -"
                                              for b, p in zip(BACKENDS, v))
                  + "; under the paper's force " + ", ".join(f"{b.upper()} {p.change:+.2f} rad" if p else
                                                             f"{b.upper()} not measured" for b, p in zip(BACKENDS, paper)),
                  literal=all(p is not None and abs(p.change) > math.pi for p in paper),
                  checks=checks_of(res, "section 5, flag"),
                  holds_when="under the energy-consistent force; the paper's force (14) does not give it on both backends")]
