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

The paper's force (14) on the same scene. Section 5 sets xi = 0 (Figs 3-5;
the flag's xi is not given), so the flag runs under the paper's force at xi =
0 as well as at the shipped flag's own xi. A run that stops before the
analysis window ends has no phase profile: it judges nothing, and the claim's
verdict says which runs stopped, when, and what the run recorded about why
(:func:`stopped`): under the paper's force the stretching coefficient is
lagged, and ``deformable run`` steps it at half the stretching bound for
G = 1, ``dt_c = sqrt(2 mu / (eta G lambda_m))`` (claim 3a); a fibre stretched
past twice its length (G_ii > 4, the study's "runaway") takes that step past
the bound, and the run diverges.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from validation.harness.backends import BACKENDS
from validation.harness.study import Figure, Table

from .analysis import classify
from .cases import RUNAWAY_G, scene_grids
from .claims import Claim, checks_of
from .pictures import panels_figure

__all__ = ["AMPLITUDE_FLOOR", "AMPLITUDE_TIP", "driving_component", "phase_along", "PhaseProfile", "window",
           "run_phase", "stopped", "why_stopped", "paper_force_claim", "measure"]

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


def stopped(run: dict) -> str:
    """What a run that has no phase profile recorded: its class, the time it reached (s) and its largest G_ii
    (sampled every 0.1 s). ``run``: status, t, Gmax."""
    G = run.get("Gmax", math.nan)
    return f"{run['status']} at t = {run['t']:.3g} s" + (f", max G_ii {G:.2f}" if np.isfinite(G) else "")


def why_stopped(runs: list) -> str:
    """Why runs under the paper's force stopped, as far as they recorded it: when every one ran away first (max
    G_ii above :data:`RUNAWAY_G`), the lagged stretching step (module docstring); otherwise nothing is said."""
    if not runs or not all(r.get("force_model") == "tpbf87" and np.isfinite(r.get("Gmax", math.nan))
                           and r["Gmax"] > RUNAWAY_G for r in runs):
        return ""
    dts = sorted({r["dt"] for r in runs})
    return (f"each had a fibre stretched past twice its length first (max G_ii {min(r['Gmax'] for r in runs):.2f} "
            f"to {max(r['Gmax'] for r in runs):.2f} > {RUNAWAY_G:g}), which puts its step (dt = "
            f"{', '.join(f'{v:.2g}' for v in dts)} s, half the lagged stretching bound at G = 1) above the bound "
            "sqrt(2 mu / (eta G lambda_m)) (claim 3a)")


def paper_force_claim(energy: dict, paper: dict, window_: tuple) -> dict:
    """The flag's claim, "a coil force on one side makes the flag wave", judged from what was measured.

    ``energy``: {backend: PhaseProfile or None} under the energy-consistent force; ``paper``: {(backend, xi):
    (PhaseProfile or None, run)} under the paper's force (14), ``run`` as :func:`stopped` takes it;
    ``window_``: the analysis window (s). A run with a profile judges the claim (a wave: the phase changes by
    more than pi from pole to tip); a run without one judges nothing, and is named in ``not_judged``.
    Returns literal (every measured run waves; False when none was measured), measured, holds_when and
    not_judged (texts for :class:`~validation.studies.paper.claims.Claim`).
    """
    lo, hi = window_

    def wave(p):
        return abs(p.change) > math.pi

    judged = [p for p in energy.values() if p is not None] + [p for p, _ in paper.values() if p is not None]
    energy_text = ", ".join(f"{b.upper()} {p.change:+.2f} rad" if p else f"{b.upper()} not measured"
                            for b, p in energy.items())
    paper_text = "; ".join(f"{b.upper()} xi = {xi:g}: " + (f"phase change {p.change:+.2f} rad" if p else stopped(r))
                           for (b, xi), (p, r) in sorted(paper.items()))
    measured = f"phase change pole to tip {energy_text} (energy-consistent); under the paper's force (14): {paper_text}"
    unmeasured = [(b, xi) for (b, xi), (p, _) in paper.items() if p is None]
    why = why_stopped([paper[k][1] for k in unmeasured])
    names = ", ".join(f"{b.upper()} xi = {xi:g}" for b, xi in sorted(unmeasured))
    not_judged = (f"under the paper's force (14) at {names}: no run reached the end of the analysis window (t = "
                  f"{lo:g} .. {hi:g} s){f'; {why}' if why else ''}; no conclusion on whether the paper's force gives "
                  "the travelling wave" if unmeasured else "")
    waving = [f"{b.upper()} xi = {xi:g}" for (b, xi), (p, _) in sorted(paper.items()) if p is not None and wave(p)]
    flat = [f"{b.upper()} xi = {xi:g} ({p.change:+.2f} rad)" for (b, xi), (p, _) in sorted(paper.items())
            if p is not None and not wave(p)]
    holds_when = "under the energy-consistent force" + (f" and the paper's at {', '.join(waving)}" if waving else "")
    if flat:
        holds_when += f"; under the paper's force (14) at {', '.join(flat)} the phase changes by less than pi"
    return dict(literal=bool(judged) and all(wave(p) for p in judged), measured=measured, holds_when=holds_when,
                not_judged=not_judged)


def measure(res, R: dict, s: dict) -> list:
    """Section 5 (Figs 7-8): the phase of the driving component along the flag, both backends and force models.

    Checks (the shipped flag, energy-consistent model, both backends): a travelling wave, the phase changing
    by more than pi from pole to tip; travelling from the pole to the free edge (the phase lag increasing
    along the flag), as a real flag's waves do; its amplitude at the free edge at least :data:`AMPLITUDE_TIP`
    of the flag's length (Figs 7-8's large waves). Reported: the phase speed. The paper's force (14), at xi = 0
    (section 5's) and at the shipped flag's xi, judges the claim where its runs reach the end of the analysis
    window, and is named as not judged where they do not (:func:`paper_force_claim`).
    """
    P, runs, rows = _phases(R, s)
    cfg = R[("flag", "fd", "variational")]["config"]
    lo, hi = window(s["s5_t"], cfg["ramp"], cfg["frequency"])
    res.tables.append(_table(rows, cfg, (lo, hi)))
    V = {b: next(p for (b_, fm, _), p in P.items() if b_ == b and fm == "variational") for b in BACKENDS}
    _check_waves(res, V, cfg["size"][0])
    res.data["flag"] = {f"{b}|{fm}|{xi:g}": dict(runs[(b, fm, xi)], measured=p is not None, **(
        dict(change=p.change, speed=p.speed, direction=p.direction, a=p.a, phase=p.phase, amplitude=p.amplitude)
        if p else {})) for (b, fm, xi), p in P.items()}
    res.findings.append(
        "Section 5, flag: " + "; ".join(
            f"{b.upper()} {fm} xi = {xi:g}: " + (f"phase change {p.change:+.2f} rad, phase speed {p.speed:.2f} m/s "
                                                 f"{p.direction}" if p else
                                                 f"{stopped(runs[(b, fm, xi)])}, not measured")
            for (b, fm, xi), p in P.items())
        + ". The coils shake the flag beside the pole and the flow's pull puts it in a tension that falls to nothing "
          "at the free edge: the waves travel from the pole to the free edge, slowing and growing on the way "
          "(deformable.scenes, 'flag').")
    res.figures.append(_phase_figure(P, cfg["frequency"]))
    c = paper_force_claim(V, {(b, xi): (p, runs[(b, fm, xi)]) for (b, fm, xi), p in P.items() if fm == "tpbf87"},
                          (lo, hi))
    return [Claim("Figs 7-8: a coil force on one side makes the flag wave", "5", c["measured"], literal=c["literal"],
                  checks=checks_of(res, "section 5, flag"), holds_when=c["holds_when"], not_judged=c["not_judged"])]


def _phases(R: dict, s: dict) -> tuple[dict, dict, list]:
    """The flag's runs, energy-consistent first, by (backend, force model, xi): their phase profiles (None where
    not measured), their records as :func:`stopped` takes them, and the rows of the flag table."""
    n = dict(zip(BACKENDS, scene_grids(s, "flag")))
    P, runs, rows = {}, {}, []
    keys = sorted((k for k in R if k[0] == "flag"), key=lambda k: (BACKENDS.index(k[1]), k[2] != "variational",
                                                                  -R[k]["config"]["xi"]))
    for k in keys:
        b, fm, r = k[1], k[2], R[k]
        xi = r["config"]["xi"]
        p = P[(b, fm, xi)] = run_phase(r, s["s5_t"])
        runs[(b, fm, xi)] = dict(status=r["status"], t=r["t"], Gmax=r.get("Gmax", math.nan), dt=r["dt"],
                                 force_model=fm, xi=xi)
        grid = f"{n[b]}x{n[b]} nodes" if b == "fd" else f"{n[b] - 1}x{n[b] - 1} el."
        rows.append((b.upper(), grid, fm, xi, classify(r), r["t"], r["dt"], r.get("Gmax", math.nan),
                     p.change if p else math.nan, p.speed if p else math.nan, p.direction if p else "not measured",
                     float(np.nanmax(p.amplitude)) if p else math.nan))
    return P, runs, rows


def _table(rows: list, cfg: dict, window_: tuple) -> Table:
    lo, hi = window_
    return Table(
        "flag", "Section 5 (Figs 7-8): the flag's wave, phase of the driving component along the middle row",
        ("backend", "grid", "force model", "xi (N m)", "class", "t reached (s)", "dt (s)", "max G_ii (sampled)",
         "phase change pole to tip (rad)", "phase speed (m/s)", "wave travels", "largest amplitude (m)"), rows,
        note=f"The shipped flag (deformable.scenes.flag: coils swinging at {cfg['frequency']:g} Hz beside the pole, "
             f"wind and the flow's pull along the flag), y along a2 = L2 / 2 fitted over t = {lo:g} .. {hi:g} s with "
             "c0 + c1 t + a cos(w t) "
             "+ b sin(w t) at each point; phase lag unwrapped from the pole over the points with at least "
             f"{AMPLITUDE_FLOOR:.0%} of the largest amplitude; phase speed w / |d phi / d a1| (m/s along the flag; "
             "module docstring of validation.studies.paper.flag). The paper's force (tpbf87) at xi = 0 (section 5's) "
             "and at the shipped flag's xi; 'max G_ii (sampled)': every 0.1 s; a run that stops before the window "
             "ends is not measured.")


def _check_waves(res, V: dict, length: float) -> None:
    """The checks of the energy-consistent flag: ``V`` {backend: PhaseProfile or None}, ``length`` L1 (m)."""
    res.check_all("section 5, flag: a travelling wave on both backends",
                  "the driving component's phase changes by more than pi from pole to tip (energy-consistent model)",
                  {f"{b.upper()} ({abs(V[b].change):.2f} rad)" if V[b] else
                   f"{b.upper()} (run did not finish)": bool(V[b]) and
                   abs(V[b].change) > math.pi for b in BACKENDS})
    res.check_all("section 5, flag: the waves travel from the pole to the free edge",
                  "the phase lag increases from pole to tip (a wave cos(w t - k a1), k > 0; energy-consistent model)",
                  {f"{b.upper()} ({V[b].direction}, {V[b].speed:.2f} m/s)"
                   if V[b] else f"{b.upper()} (run did not finish)":
                   bool(V[b]) and V[b].direction == "towards the tip"
                   for b in BACKENDS})
    res.check_all(f"section 5, flag: waves at least {AMPLITUDE_TIP:g} of the flag's length at its free edge",
                  f"the driving component's amplitude at the tip >= {AMPLITUDE_TIP:g} L1 = "
                  f"{AMPLITUDE_TIP * length:g} m "
                  "(energy-consistent model)",
                  {f"{b.upper()} ({V[b].amplitude[-1]:.3f} m)" if V[b] else
                   f"{b.upper()} (run did not finish)": bool(V[b]) and
                   V[b].amplitude[-1] >= AMPLITUDE_TIP * length for b in BACKENDS})


def _phase_figure(P: dict, frequency: float) -> Figure:
    """Phase lag and amplitude along the flag of every measured run (``P`` as :func:`_phases` gives it)."""
    style = {"fd": "tab:blue", "fe": "tab:orange"}
    phase_lines, amp_lines = [], []
    for (b, fm, xi), p in P.items():
        if p is None:
            continue
        st = "-" if fm == "variational" else "--"
        phase_lines.append(dict(x=p.a, y=p.phase, style=st, color=style[b], label=f"{b.upper()} {fm} xi={xi:g}"))
        amp_lines.append(dict(x=p.a, y=p.amplitude, style=st, color=style[b], label=f"{b.upper()} {fm} xi={xi:g}"))
    return Figure("flag_phase", "Section 5: the flag's driving component along the middle row, pole (0) "
                  "to tip: phase lag (left; increasing towards the tip = a wave travelling towards the "
                  "tip) and amplitude (right)",
                  image=panels_figure([
                      dict(title=f"phase lag of the {frequency:g} Hz component", xlabel="a1 (m)",
                           ylabel="phi (rad)", lines=phase_lines),
                      dict(title="amplitude", xlabel="a1 (m)", ylabel="R (m)", lines=amp_lines)],
                      "The flag's wave"))
