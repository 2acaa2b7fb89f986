#!/usr/bin/env python3
"""cierva's identification estimator (`cierva_harness::ident`), written again in numpy.

The same estimator as `cierva identify`, step for step, so that the two can be timed side by
side (issue 32: "the identification rows: at least 10x a numpy implementation of the same
estimator") and shown to compute the same numbers (`--check`):

1. air data to the centre of mass (seed 000 Eqs. 5-6): the probe's velocity from airspeed and
   vanes, less `omega x r` of the probe's offset; every state and control as a perturbation
   about the sidecar's trim (`ident::signals`);
2. the finite Fourier integral by the trapezoidal rule at the set-up's frequencies (evenly
   spaced: a chirp-z transform by Bluestein's algorithm, the FFT length `n + m - 1` rounded up
   to a power of two, as `ident::fourier::ChirpZ`; a list: the direct sum), per segment, with
   the optional Hann taper; the derivative's transform exactly for a finite tapered record,
   `F[w x'] = i w F[w x] - F[w' x] + w(T) x(T) e^(-i w T) - w(0) x(0)` (`estimate::spectra`);
3. each force equation by complex least squares, real and imaginary parts as rows, columns
   scaled to unit norm, solved by SVD (`estimate::fit`);
4. with instrumental variables (the default), two passes: the instruments are the first model's
   response `(i w I - A)^-1 B U(w)` to the measured controls (`estimate::identify_iv`);
5. sandwich (heteroscedasticity-consistent) standard errors, `n / (n - p)` small-sample factor,
   each frequency's variance its own squared residual (real and imaginary pooled); 95 % bounds
   from Student's t by the same Cornish-Fisher expansion.

Vectorised: the transforms of every signal in one batched FFT, the instruments by one batched
complex solve over the frequencies, the equations that share their regressors in one SVD. No
Python loop runs over samples or frequencies.

Usage:
  scripts/ident_numpy.py RECORD.csv [--points 100] [--format text|json]
      identify (the longitudinal set-up, `ConfigSpec::longitudinal`, as `cierva bench`'s rows);
  scripts/ident_numpy.py RECORD.csv --repeat 21
      time the estimator on the record in memory (air data to c.g. onward, as the Rust row
      times `ident::identify_record`; reading and parsing the CSV is excluded): prints JSON
      `{"times_s": [...], ...}`;
  scripts/ident_numpy.py RECORD.csv --check [--cierva target/release/cierva]
      run `cierva identify RECORD --config C --format json` with the same set-up and compare
      every estimate and standard error (exit 1 if any differs by more than the tolerance).

Needs numpy; PyYAML is used for the sidecar when it is installed, else a small reader of the
fields needed (`sample_rate_hz`, `sensors`, `trim`, `controls`) as cierva writes them.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time

try:
    import numpy as np
except ImportError:  # said plainly, so that `cierva bench` can report it
    print("numpy is not installed (pip install numpy)", file=sys.stderr)
    sys.exit(3)

FORCE_STATES = {"u": "X", "v": "Y", "w": "Z", "p": "L", "q": "M", "r": "N", "Omega": "Q"}
FLAP_STATES = ("beta_1c", "beta_1s")
HIGH_CORRELATION = 0.95
LARGE_RELATIVE_ERROR = 0.5
ILL_CONDITIONED = 1e6


class IdentError(Exception):
    """What `IdentError` says in Rust: the estimation cannot be done."""


# --- the record ----------------------------------------------------------------------------


def _scalar(text):
    text = text.strip().strip("'\"")
    try:
        return float(text)
    except ValueError:
        return text


def _flow(text):
    """A flow list `[a, b]` or mapping `{a: 1, b: 2}` of scalars."""
    text = text.strip()
    body = text[1:-1].strip()
    items = [i for i in body.split(",") if i.strip()] if body else []
    if text.startswith("["):
        return [_scalar(i) for i in items]
    return {k.strip(): _scalar(v) for k, v in (i.split(":", 1) for i in items)}


def _read_sidecar_small(text):
    """The sidecar's `sample_rate_hz`, `sensors`, `trim` and `controls`, as serde_yaml writes
    them (block mappings; lists at their key's indent or deeper) or in flow style."""
    lines = [l.rstrip() for l in text.splitlines() if l.strip() and not l.lstrip().startswith("#")]
    out, i = {}, 0
    while i < len(lines):
        line = lines[i]
        i += 1
        if line[0] in " -" or ":" not in line:
            continue
        key, rest = (s.strip() for s in line.split(":", 1))
        if key not in ("sample_rate_hz", "sensors", "trim", "controls"):
            continue
        if rest:
            out[key] = _flow(rest) if rest[0] in "[{" else _scalar(rest)
            continue
        block = []
        while i < len(lines) and lines[i][0] in " -":
            block.append(lines[i])
            i += 1
        if all(b.lstrip().startswith("- ") for b in block):
            out[key] = [_scalar(b.lstrip()[2:]) for b in block]
            continue
        mapping, j = {}, 0
        while j < len(block):
            k, v = (s.strip() for s in block[j].split(":", 1))
            j += 1
            if v:
                mapping[k] = _flow(v) if v[0] in "[{" else _scalar(v)
            else:
                items = []
                while j < len(block) and block[j].lstrip().startswith("- "):
                    items.append(_scalar(block[j].lstrip()[2:]))
                    j += 1
                mapping[k] = items
        out[key] = mapping
    return out


def current_name(name):
    """`inputs::record::current_name`: the old spelling `<x>_pct` is `<x>_percent`."""
    return name[: -len("_pct")] + "_percent" if name.endswith("_pct") and name != "_pct" else name


def _current_names(names, where):
    """Names in today's spelling; one channel spelled both ways is an error, as in cierva."""
    out = [current_name(n) for n in names]
    for i, n in enumerate(out):
        if n in out[:i] and names[out.index(n)] != names[i]:
            raise IdentError(f"{where}: `{names[out.index(n)]}` and `{names[i]}` are one channel")
    return out


def read_record(csv_path):
    """Channels (name -> samples) and the sidecar's fields the estimator needs, names in
    today's spelling (`current_name`)."""
    with open(csv_path) as f:
        header = [h.strip() for h in f.readline().strip().split(",")]
    header = _current_names(header, csv_path)
    data = np.loadtxt(csv_path, delimiter=",", skiprows=1, ndmin=2)
    channels = {name: np.ascontiguousarray(data[:, i]) for i, name in enumerate(header)}
    sidecar = os.path.splitext(csv_path)[0] + ".yaml"
    with open(sidecar) as f:
        text = f.read()
    try:
        import yaml  # PyYAML, when installed

        meta = yaml.safe_load(text)
    except ImportError:
        meta = _read_sidecar_small(text)
    if meta.get("controls"):
        meta["controls"] = _current_names(list(meta["controls"]), sidecar)
    if meta.get("trim"):
        keys = list(meta["trim"])
        meta["trim"] = dict(zip(_current_names(keys, sidecar), meta["trim"].values()))
    return channels, meta


# --- the set-up -----------------------------------------------------------------------------


def longitudinal(meta, points=100, from_hz=0.05, to_hz=2.0, method="instrumental_variables",
                 segments=1, overlap=0.0, hann=False):
    """`ConfigSpec::longitudinal`: `[u w q theta Omega]`, the record's first control,
    0.05-2 Hz at 100 points, theta' = q, instrumental variables (the bench's set-up)."""
    controls = {}
    if meta.get("controls"):
        c = meta["controls"][0]
        name = c[: -len("_rad")] if c.endswith("_rad") else c[: -len("_percent")] if c.endswith("_percent") else c
        controls[name] = c
    return {
        "states": ["u", "w", "q", "theta", "Omega"],
        "controls": controls,
        "frequencies": {"from_hz": from_hz, "to_hz": to_hz, "points": points},
        "windowing": {"segments": segments, "overlap": overlap, "hann": hann},
        "kinematics": {"theta": "q"},
        "method": method,
    }


def config_yaml(cfg):
    """The set-up as `cierva identify --config` reads it."""
    f, w = cfg["frequencies"], cfg["windowing"]
    lines = ["states: [" + ", ".join(cfg["states"]) + "]", "controls:"]
    lines += [f"  {k}: {v}" for k, v in sorted(cfg["controls"].items())]
    lines += [
        "frequencies:",
        f"  from_hz: {f['from_hz']!r}",
        f"  to_hz: {f['to_hz']!r}",
        f"  points: {f['points']}",
        "windowing:",
        f"  segments: {w['segments']}",
        f"  overlap: {w['overlap']!r}",
        f"  hann: {'true' if w['hann'] else 'false'}",
        "kinematics:",
    ]
    lines += [f"  {k}: {v}" for k, v in sorted(cfg["kinematics"].items())]
    lines.append(f"method: {cfg['method']}")
    return "\n".join(lines) + "\n"


# --- the estimator --------------------------------------------------------------------------


def signals(channels, meta, cfg):
    """`ident::signals`: the states' and controls' perturbation histories, `(n_var, n)`."""
    trim = meta.get("trim") or {}
    v, a, b = channels["airspeed_m_s"], channels["alpha_vane_rad"], channels["beta_vane_rad"]
    p, q, r = channels["p_rad_s"], channels["q_rad_s"], channels["r_rad_s"]
    s = meta.get("sensors")
    if not s:
        raise IdentError("the sidecar gives no `sensors` (probe and c.g. positions)")
    off = [float(s["probe_position_m"][i]) - float(s["cg_position_m"][i]) for i in range(3)]
    cb = np.cos(b)
    u = v * cb * np.cos(a) - (q * off[2] - r * off[1])
    vv = v * np.sin(b) - (r * off[0] - p * off[2])
    w = v * cb * np.sin(a) - (p * off[1] - q * off[0])
    derived = {"u": (u, "u_m_s"), "v": (vv, "v_m_s"), "w": (w, "w_m_s")}
    rows = []
    for st in cfg["states"]:
        if st in derived:
            series, key = derived[st]
        elif st in ("p", "q", "r"):
            key = f"{st}_rad_s"
            series = channels[key]
        elif st in ("phi", "theta", "psi"):
            key = f"{st}_rad"
            series = channels[key]
        elif st == "Omega":
            key = "omega_rotor_rad_s"
            series = channels[key]
        else:
            raise IdentError(f"no measurement gives the state `{st}` (not written in numpy)")
        rows.append(series - float(trim.get(key, 0.0)))
    for _, channel in sorted(cfg["controls"].items()):
        rows.append(channels[channel] - float(trim.get(channel, 0.0)))
    return np.array(rows)


def omegas_of(cfg):
    """`Frequencies::omegas`, rad/s, computed in the same order of operations."""
    f = cfg["frequencies"]
    two_pi = 2.0 * math.pi
    if f.get("list_hz"):
        return np.array([two_pi * x for x in f["list_hz"]]), False
    a, b, n = f["from_hz"], f["to_hz"], f["points"]
    k = np.arange(n, dtype=float)
    return two_pi * (a + (b - a) * k / (n - 1)), n > 1


class ChirpZ:
    """`ident::fourier::ChirpZ`: the trapezoidal finite Fourier integral of `n` samples at the
    `m` frequencies `w0 + k dw` by Bluestein's algorithm, prepared once per segment length."""

    def __init__(self, n, dt, w0, dw, m):
        length = 1 << max(n + m - 2, 0).bit_length()  # next power of two >= n + m - 1
        th0, phi = w0 * dt, dw * dt
        k = np.arange(max(n, m), dtype=float)
        chirp = np.exp(1j * (-phi * k * k / 2.0))
        kernel = np.zeros(length, dtype=complex)
        kernel[:m] = np.conj(chirp[:m])
        if n > 1:
            kernel[length - n + 1:] = np.conj(chirp[1:n])[::-1]
        self.kernel = np.fft.fft(kernel)  # numpy's inverse FFT carries the 1 / length
        self.length, self.n, self.m, self.dt = length, n, m, dt
        self.pre = np.exp(1j * (-th0 * k[:n])) * chirp[:n]
        self.post = chirp[:m]
        last = float(max(n - 1, 0))
        self.end = np.exp(1j * (-(w0 + np.arange(m, dtype=float) * dw) * dt * last))

    def apply(self, x):
        """The transforms of the rows of `x`, `(signals, n)` -> `(signals, m)`."""
        y = np.fft.ifft(np.fft.fft(self.pre * x, n=self.length, axis=-1) * self.kernel, axis=-1)
        s = y[:, : self.m] * self.post
        return (s - (self.end * x[:, -1:] + x[:, :1]) * 0.5) * self.dt


def direct_transform(x, dt, omegas):
    """`ident::fourier::transform`: the trapezoidal sum at any list of frequencies."""
    n = x.shape[1]
    e = np.exp(-1j * np.outer(omegas, np.arange(n) * dt))
    s = x @ e.T
    return (s - (e[:, -1] * x[:, -1:] + x[:, :1]) * 0.5) * dt


def hann(n, dt):
    t = (max(n, 2) - 1) * dt
    k = np.arange(n, dtype=float)
    return 0.5 - 0.5 * np.cos(2.0 * math.pi * k * dt / t), math.pi / t * np.sin(2.0 * math.pi * k * dt / t)


def spectra(series, n_states, dt, cfg):
    """`estimate::spectra`: the transforms of every variable and of each state's derivative,
    stacked over segments. Returns (omegas per point, var_ft (n_var, pts), der_ft (n_states, pts))."""
    omegas, uniform = omegas_of(cfg)
    if not np.all(np.isfinite(series)):
        raise IdentError("a signal is not finite")
    w_cfg = cfg["windowing"]
    segs, overlap = w_cfg["segments"], w_cfg["overlap"]
    n = series.shape[1]
    k = float(segs)
    seg_len = int(math.floor(n / (k - (k - 1.0) * overlap)))
    hop = max(int(math.floor((1.0 - overlap) * seg_len + 0.5)), 1)  # Rust's round: half away from zero
    segment_s = (max(seg_len, 1) - 1) * dt
    lowest_hz = float(omegas.min()) / (2.0 * math.pi)
    if lowest_hz < 2.0 / segment_s:
        raise IdentError(f"the record is too short for the band ({segment_s:.1} s segments)")
    plans = {}
    var_parts, der_parts = [], []
    for s in range(segs):
        start = s * hop
        end = min(start + seg_len, n)
        seg = series[:, start:end]
        length = end - start
        if uniform:
            plan = plans.get(length)
            if plan is None:
                plan = plans[length] = ChirpZ(length, dt, omegas[0], omegas[1] - omegas[0], len(omegas))
            ft = plan.apply
        else:
            ft = lambda x: direct_transform(x, dt, omegas)  # noqa: E731
        t_end = (length - 1) * dt
        if w_cfg["hann"]:
            w, dw = hann(length, dt)
            fwx = ft(seg * w)
            fdw = ft(seg[:n_states] * dw)
            x0, xt = w[0] * seg[:n_states, :1], w[-1] * seg[:n_states, -1:]
        else:
            # No taper: w = 1 and w' = 0, so F[w' x] is zero (Rust transforms the zeros).
            fwx = ft(seg)
            fdw = 0.0
            x0, xt = seg[:n_states, :1], seg[:n_states, -1:]
        der = 1j * omegas * fwx[:n_states] - fdw + xt * np.exp(1j * (-omegas * t_end)) - x0
        var_parts.append(fwx)
        der_parts.append(der)
    stacked = np.tile(omegas, segs)
    return stacked, np.concatenate(var_parts, axis=1), np.concatenate(der_parts, axis=1)


def student_t_975(dof):
    """`estimate::student_t_975`: Cornish-Fisher about the normal quantile."""
    z = 1.959963984540054
    v = float(max(dof, 1))
    z3, z5, z7 = z**3, z**5, z**7
    return (z + (z3 + z) / (4.0 * v) + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * v * v)
            + (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / (384.0 * v * v * v))


def _rows(c):
    """Complex `(m, ...)` to real `(2m, ...)`, real and imaginary parts interleaved (2k, 2k+1)."""
    return np.stack([c.real, c.imag], axis=1).reshape((2 * c.shape[0],) + c.shape[1:])


def fit_equations(names, n_states, omegas, var_ft, der_ft, equations, model=None):
    """`estimate::fit_equations`: each equation by least squares or, given a first model
    `(a, b)`, by instrumental variables; equations sharing their free variables share one
    regressor matrix (one SVD, one solve for all their right-hand sides)."""
    index = {nm: i for i, nm in enumerate(names)}
    ins_ft = None if model is None else state_instruments(model[0], model[1], omegas, var_ft, n_states)
    groups = {}
    for e, eq in enumerate(equations):
        groups.setdefault(tuple(eq["estimate"]), []).append(e)
    fits = [None] * len(equations)
    m = var_ft.shape[1]
    rows = 2 * m
    for estimate, members in groups.items():
        cols = [index[v] for v in estimate]
        p = len(cols)
        if p == 0 or rows <= p:
            raise IdentError(f"{p} parameters but only {rows} equations")
        y_c = np.empty((m, len(members)), dtype=complex)
        for c, e in enumerate(members):
            eq = equations[e]
            yk = der_ft[names.index(eq["state"])]
            for v, val in eq.get("fixed", {}).items():
                yk = yk - var_ft[index[v]] * val
            y_c[:, c] = yk
        y = _rows(y_c)
        x = _rows(var_ft[cols].T)
        scales = np.linalg.norm(x, axis=0)
        if not np.all(np.isfinite(scales) & (scales > 0.0)):
            raise IdentError("the regressors are singular: a regressor is zero or not finite")
        xs = x / scales
        u, sv, vt = np.linalg.svd(xs, full_matrices=False)
        smax, smin = sv.max(), sv.min()
        if not smin > smax * 1e-13:
            raise IdentError(f"the regressors are singular (singular values {smax:.3e} to {smin:.3e})")
        dof = rows - p
        if ins_ft is None:
            theta = vt.T @ ((u.T @ y) / sv[:, None])
            zs = xs
        else:
            zs = _rows(ins_ft[cols].T) / scales
            theta = np.linalg.solve(zs.T @ xs, zs.T @ y)
        resid = y - xs @ theta
        rss = np.sum(resid**2, axis=0)
        tss = np.sum((y - y.mean(axis=0)) ** 2, axis=0)
        g_inv = np.linalg.inv(zs.T @ xs)
        small_sample = rows / dof
        s2k = 0.5 * (resid[0::2] ** 2 + resid[1::2] ** 2) * small_sample  # (m, equations)
        s2 = np.repeat(s2k, 2, axis=0)  # each point's variance on both its rows
        meat = (zs.T[None, :, :] * s2.T[:, None, :]) @ zs  # sum_r s2_r z_r z_r', per equation
        cov = g_inv @ meat @ g_inv.T  # (equations, p, p)
        t = student_t_975(dof)
        var = np.diagonal(cov, axis1=1, axis2=2)
        values = theta.T / scales
        ses = np.sqrt(var) / scales
        corr = cov / np.sqrt(var[:, :, None] * var[:, None, :])
        for c, e in enumerate(members):
            fits[e] = _equation_fit(equations[e], estimate, values[c], ses[c], t, dof, corr[c],
                                    rss[c], tss[c], smax / smin)
            fits[e]["y_norm"] = float(np.sqrt(np.sum(y[:, c] ** 2)))
            for est, scale in zip(fits[e]["estimates"], scales):
                est["column_norm"] = float(scale)
    return fits


def _equation_fit(eq, estimate, values, ses, t, dof, corr, rss, tss, cond):
    estimates = [
        {"variable": v, "value": float(val), "standard_error": float(se),
         "lower_95": float(val - t * se), "upper_95": float(val + t * se)}
        for v, val, se in zip(estimate, values, ses)
    ]
    warnings = []
    p = len(estimate)
    for a in range(p):
        for b in range(a + 1, p):
            if abs(corr[a, b]) > HIGH_CORRELATION:
                warnings.append(f"the coefficients of {estimate[a]} and {estimate[b]} are highly correlated (r = {corr[a, b]:.3f})")
        if ses[a] > LARGE_RELATIVE_ERROR * abs(values[a]):
            warnings.append(f"{estimate[a]} is poorly identified")
    if cond > ILL_CONDITIONED:
        warnings.append(f"ill-conditioned regressors (condition number {cond:.2e})")
    return {
        "state": eq["state"], "estimates": estimates, "fixed": eq.get("fixed", {}),
        "r_squared": float(1.0 - rss / tss) if tss > 0.0 else 1.0, "dof": dof,
        "residual_fraction": float(math.sqrt(rss / tss)) if tss > 0.0 else 0.0,
        "correlation": corr, "condition_number": float(cond), "warnings": warnings,
    }


def state_instruments(a, b, omegas, var_ft, n):
    """`estimate::state_instruments`: `(i w I - a)^-1 b U(w)` at every point, by one batched
    complex solve; the controls follow unchanged."""
    pts = omegas.shape[0]
    sys_ = np.broadcast_to(-a.astype(complex), (pts, n, n)).copy()
    idx = np.arange(n)
    sys_[:, idx, idx] += 1j * omegas[:, None]
    rhs = (b @ var_ft[n:]).T  # (points, n)
    try:
        z = np.linalg.solve(sys_, rhs[:, :, None])[:, :, 0]
    except np.linalg.LinAlgError:  # a singular point gives zeros, as in Rust
        z = np.zeros((pts, n), dtype=complex)
        for k in range(pts):
            try:
                z[k] = np.linalg.solve(sys_[k], rhs[k])
            except np.linalg.LinAlgError:
                pass
    return np.concatenate([z.T, var_ft[n:]], axis=0)


def identified_model(cfg, controls, fits):
    """`ident::identified_model`: the identified rows, the kinematic rows; zero elsewhere."""
    states = cfg["states"]
    n = len(states)
    a, b = np.zeros((n, n)), np.zeros((n, len(controls)))
    for f in fits:
        row = states.index(f["state"])
        pairs = [(e["variable"], e["value"]) for e in f["estimates"]] + list(f["fixed"].items())
        for name, v in pairs:
            if name in states:
                a[row, states.index(name)] = v
            else:
                b[row, controls.index(name)] = v
    for state, rate in sorted(cfg["kinematics"].items()):
        a[states.index(state), states.index(rate)] = 1.0
    return a, b


def identify(channels, meta, cfg):
    """`ident::identify_record`: from the record in memory to the derivatives."""
    controls = sorted(cfg["controls"])
    states = cfg["states"]
    names = states + controls
    full = [{"state": s, "estimate": list(names), "fixed": {}}
            for s in states if s in FORCE_STATES or s in FLAP_STATES]
    equations = cfg.get("equations") or full
    dt = 1.0 / float(meta["sample_rate_hz"])
    series = signals(channels, meta, cfg)
    omegas, var_ft, der_ft = spectra(series, len(states), dt, cfg)
    fits = fit_equations(names, len(states), omegas, var_ft, der_ft, equations)
    if cfg["method"] == "instrumental_variables":
        base = fits if equations == full else fit_equations(names, len(states), omegas, var_ft, der_ft, full)
        for _ in range(2):
            by_state = {f["state"]: f for f in fits}
            merged = [by_state.get(bf["state"], bf) for bf in base]
            model = identified_model(cfg, controls, merged)
            fits = fit_equations(names, len(states), omegas, var_ft, der_ft, equations, model)
            base = merged
    derivatives = []
    for f in fits:
        letter = FORCE_STATES.get(f["state"], f["state"])
        for e in f["estimates"]:
            derivatives.append({"name": f"{letter}_{e['variable']}", "estimate": e["value"],
                                "standard_error": e["standard_error"],
                                "lower_95": e["lower_95"], "upper_95": e["upper_95"],
                                # for --check: the size of the term in its equation, and the
                                # residual's size relative to the equation's
                                "term": e["column_norm"] / f["y_norm"],
                                "residual": f["residual_fraction"]})
    return {"fits": fits, "derivatives": derivatives,
            "status": "warnings" if any(f["warnings"] for f in fits) else "ok"}


# --- the command ----------------------------------------------------------------------------


# The tolerances of --check. The two implementations differ only in the order of their
# floating-point operations (numpy's pocketfft against rustfft, LAPACK's SVD and solves against
# nalgebra's, one batched complex solve against an LU per frequency). Rounding of about 1e-16 of
# the data, through FFTs of 16384 points and regressors of scaled condition number about 50
# (more for the instrumental variables' Z'X), moves an equation's fitted terms by 1e-14 to 1e-10
# of the equation's size (measured on the bench's records, on a noisy one, by least squares and
# with Hann segments). A difference of method (a missing end term, another frequency grid,
# another small-sample factor) moves them by 1e-3 or more.
# - An estimate: the change of its term in the equation, relative to the equation,
#   |d theta_c| |x_c| / |y|, at most ESTIMATE_TOLERANCE. Scale-free, and meaningful for a
#   derivative whose truth is zero (it has no relative digits of its own).
# - A standard error: relative, at most max(SE_TOLERANCE, RESIDUAL_ROUNDING / rho), where
#   rho = sqrt(RSS / TSS) is the residual's size relative to the equation. A standard error is
#   computed from the residuals; on a noisy record rho is 0.15-0.25 and the first term rules, but
#   on the bench's noise-free records the residual is only the transforms' discretisation error,
#   rho = 1.5e-8 to 2.6e-8, and rounding of 1e-13 of the data is 1e-5 of it (measured: 4e-6 and
#   3e-5). RESIDUAL_ROUNDING allows 1e-11 of the equation (20 times the largest measured there);
#   a 1.5 % error in the standard errors still fails there by 40 times.
ESTIMATE_TOLERANCE = 1e-9
SE_TOLERANCE = 1e-9
RESIDUAL_ROUNDING = 1e-11


def compare(ours, theirs):
    """The largest differences of estimates and standard errors from cierva's, each with what
    it is judged by (see ESTIMATE_TOLERANCE), and the plain relative ones."""
    by_name = {d["name"]: d for d in theirs["derivatives"]}
    if set(by_name) != {d["name"] for d in ours["derivatives"]}:
        raise SystemExit(f"different derivatives: {sorted(by_name)} against {[d['name'] for d in ours['derivatives']]}")
    worst = {}

    def keep(key, value, name, allowed=None):
        score = value if allowed is None else value / allowed
        if key not in worst or not score <= worst[key]["score"]:
            worst[key] = {"value": value, "derivative": name, "allowed": allowed, "score": score}

    for d in ours["derivatives"]:
        t = by_name[d["name"]]
        de = abs(d["estimate"] - t["estimate"])
        ds = abs(d["standard_error"] - t["standard_error"]) / t["standard_error"]
        keep("estimate_in_equation", de * d["term"], d["name"], ESTIMATE_TOLERANCE)
        keep("standard_error_relative", ds, d["name"],
             max(SE_TOLERANCE, RESIDUAL_ROUNDING / max(d["residual"], 1e-300)))
        keep("estimate_relative", de / abs(t["estimate"]) if t["estimate"] else math.inf, d["name"])
        keep("standard_error_plain", ds, d["name"])
    ok = all(w["score"] <= 1.0 for w in worst.values() if w["allowed"] is not None)
    return ok, worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("record", help="RECORD.csv, with RECORD.yaml beside it")
    ap.add_argument("--points", type=int, default=100)
    ap.add_argument("--from-hz", type=float, default=0.05)
    ap.add_argument("--to-hz", type=float, default=2.0)
    ap.add_argument("--method", choices=["instrumental_variables", "least_squares"],
                    default="instrumental_variables")
    ap.add_argument("--segments", type=int, default=1)
    ap.add_argument("--overlap", type=float, default=0.0)
    ap.add_argument("--hann", action="store_true")
    ap.add_argument("--format", choices=["text", "json"], default="text")
    ap.add_argument("--repeat", type=int, help="time the estimator this many times (JSON out)")
    ap.add_argument("--check", action="store_true", help="compare with `cierva identify`")
    ap.add_argument("--cierva", default="target/release/cierva", help="the cierva binary (--check)")
    a = ap.parse_args()

    try:
        channels, meta = read_record(a.record)
    except IdentError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    cfg = longitudinal(meta, a.points, a.from_hz, a.to_hz, a.method, a.segments, a.overlap, a.hann)
    try:
        if a.repeat:
            times, result = [], None
            for _ in range(a.repeat):
                t0 = time.perf_counter()
                result = identify(channels, meta, cfg)
                times.append(time.perf_counter() - t0)
            print(json.dumps({"times_s": times, "derivatives": len(result["derivatives"]),
                              "numpy": np.__version__, "samples": len(channels["time_s"])}))
            return 0
        result = identify(channels, meta, cfg)
    except IdentError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    if a.check:
        with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
            f.write(config_yaml(cfg))
        try:
            out = subprocess.run([a.cierva, "identify", a.record, "--config", f.name, "--format", "json"],
                                 check=True, capture_output=True, text=True).stdout
        finally:
            os.unlink(f.name)
        ok, worst = compare(result, json.loads(out))
        if a.format == "json":
            print(json.dumps({"ok": ok, "record": a.record, **worst}))
        else:
            e, se = worst["estimate_in_equation"], worst["standard_error_relative"]
            er, sp = worst["estimate_relative"], worst["standard_error_plain"]
            print(f"{a.record}: {len(result['derivatives'])} derivatives against cierva's: "
                  f"{'agree' if ok else 'DIFFER'}. Estimates: their terms differ by at most "
                  f"{e['value']:.1e} of the equation ({e['derivative']}; allowed {e['allowed']:.0e}), "
                  f"{er['value']:.1e} of the estimate ({er['derivative']}). Standard errors: at most "
                  f"{sp['value']:.1e} relative ({sp['derivative']}); nearest its allowance "
                  f"{se['value']:.1e} ({se['derivative']}; allowed {se['allowed']:.1e} there)")
        return 0 if ok else 1
    if a.format == "json":
        print(json.dumps({k: v for k, v in result.items() if k != "fits"}))
    else:
        for d in result["derivatives"]:
            print(f"{d['name']:>12} {d['estimate']: .9e} +- {d['standard_error']:.3e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
