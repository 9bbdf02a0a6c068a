"""An independent ride simulator for the tests: where a follower sits on a cam as made.

Given a cam (a :class:`camgen.contour.Contour`, or a closed polygon of points) and the follower
geometry, find the follower position at cam angle ``theta`` from contact geometry alone, without
any of camgen.synthesis.followers' formulas:

* translating roller: the highest roller-centre height ``y`` on the line ``x = offset`` at which
  the roller touches the rotated cam;
* translating knife: the highest point of the rotated cam on the line ``x = offset``;
* translating flat face (normal to ``+y``): the highest point of the rotated cam (support function);
* oscillating roller / knife: the arm angle (rad, fixed frame) of the most lifted arm position
  touching the cam, near the rest angle;
* oscillating flat face: the angle of the face normal at the most lifted position touching it.

A dense polygon of the cam gives the candidates (closed-form contact of each vertex), then
Newton steps on the exact contour (its segments' own derivatives) polish the contact so the
position resolves 1e-8 mm.  With ``return_param=True`` every function also returns the contour
parameter of the contact (``cam.evaluate(t)`` is the contact point in the cam frame).  The cam turns by ``sigma theta`` (``sigma = +1`` ccw, ``-1`` cw): a
cam point ``q`` is at ``R(sigma theta) q``.
"""
from __future__ import annotations

import math

import numpy as np

from camgen.contour import Arc, Contour

#: chord tolerance (mm) of the polygon that seeds the Newton steps
SEED_CHORD_TOL = 2e-3
#: Newton iterations and their stopping step (global contour parameter)
NEWTON_STEPS = 30
NEWTON_TOL = 1e-14


def _rot(angle: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """Points (N, 2) rotated by every angle (M,): (M, N, 2)."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    return np.stack([c * pts[None, :, 0] - s * pts[None, :, 1], s * pts[None, :, 0] + c * pts[None, :, 1]], axis=-1)


def _rot1(angle: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Vectors (M, 2) rotated by angles (M,)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]], axis=-1)


def contour_derivatives(contour: Contour, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Point, d/dt and d2/dt2 (each (M, 2)) of the contour at global parameters ``t`` (M,).

    Arc segments are evaluated together from a table of their centres, radii and angles (a
    biarc chain read back from a DXF has thousands); other segments one by one."""
    n = contour.n_segments
    flat = np.mod(np.asarray(t, dtype=float), n)
    idx = np.minimum(np.floor(flat).astype(int), n - 1)
    u = flat - idx
    p, d1, d2 = (np.empty((flat.size, 2)) for _ in range(3))
    table = _arc_table(contour)
    is_arc = table[5][idx]
    if is_arc.any():
        cx, cy, r, a0, sweep = (col[idx[is_arc]] for col in table[:5])
        a = a0 + sweep * u[is_arc]
        c, s = np.cos(a), np.sin(a)
        p[is_arc] = np.stack([cx + r * c, cy + r * s], axis=1)
        d1[is_arc] = (r * sweep)[:, None] * np.stack([-s, c], axis=1)
        d2[is_arc] = -(r * sweep**2)[:, None] * np.stack([c, s], axis=1)
    for i in np.unique(idx[~is_arc]):
        m = idx == i
        seg = contour.segments[i]
        p[m], d1[m], d2[m] = seg.point(u[m]), seg.derivative(u[m]), seg.second_derivative(u[m])
    return p, d1, d2


def _arc_table(contour: Contour) -> tuple[np.ndarray, ...]:
    """Columns (cx, cy, radius, start angle, sweep, is_arc) over the contour's segments (cached)."""
    cached = getattr(contour, "_ride_arc_table", None)
    if cached is not None:
        return cached
    rows = [(seg.center[0], seg.center[1], seg.radius, seg.start_angle, seg.sweep, 1.0) if isinstance(seg, Arc) else (0.0,) * 6
            for seg in contour.segments]
    cols = np.array(rows, dtype=float).T
    contour._ride_arc_table = (cols[0], cols[1], cols[2], cols[3], cols[4], cols[5] > 0)  # type: ignore[attr-defined]
    return contour._ride_arc_table  # type: ignore[attr-defined]


def _seed(cam: Contour | np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    if isinstance(cam, Contour):
        params = cam.flatten_params(SEED_CHORD_TOL)
        return cam.evaluate(params), params
    return np.asarray(cam, dtype=float), None


def _chunks(m: int, n: int, budget: int = 2_000_000):
    step = max(1, budget // max(1, n))
    for lo in range(0, m, step):
        yield slice(lo, min(m, lo + step))


def _newton_1d(contour: Contour, theta_rot: np.ndarray, t: np.ndarray, residual) -> np.ndarray:
    """Newton on a scalar condition ``residual(X, X', X'') -> (g, dg/dt)`` in the contour parameter."""
    for _ in range(NEWTON_STEPS):
        p, d1, d2 = contour_derivatives(contour, t)
        g, dg = residual(_rot1(theta_rot, p), _rot1(theta_rot, d1), _rot1(theta_rot, d2))
        step = np.where(dg != 0, g / np.where(dg != 0, dg, 1.0), 0.0)
        step = np.clip(step, -0.05, 0.05)
        t = t - step
        if np.max(np.abs(step)) < NEWTON_TOL * contour.n_segments:
            break
    return t


def _newton_2d(contour: Contour, theta_rot: np.ndarray, t: np.ndarray, a: np.ndarray, system) -> tuple[np.ndarray, np.ndarray]:
    """Newton on two conditions ``system(X, X', X'', a) -> (F (M, 2), Jacobian (M, 2, 2))`` in (t, a)."""
    for _ in range(NEWTON_STEPS):
        p, d1, d2 = contour_derivatives(contour, t)
        f, jac = system(_rot1(theta_rot, p), _rot1(theta_rot, d1), _rot1(theta_rot, d2), a)
        det = jac[:, 0, 0] * jac[:, 1, 1] - jac[:, 0, 1] * jac[:, 1, 0]
        det = np.where(det != 0, det, 1.0)
        dt = (jac[:, 1, 1] * f[:, 0] - jac[:, 0, 1] * f[:, 1]) / det
        da = (-jac[:, 1, 0] * f[:, 0] + jac[:, 0, 0] * f[:, 1]) / det
        dt, da = np.clip(dt, -0.05, 0.05), np.clip(da, -0.05, 0.05)
        t, a = t - dt, a - da
        if max(np.max(np.abs(dt)), np.max(np.abs(da))) < NEWTON_TOL * contour.n_segments:
            break
    return t, a


# --------------------------------------------------------------------------------------------
# Translating followers (moving along +y on the line x = offset)
# --------------------------------------------------------------------------------------------
def translating_roller(cam, theta, offset: float, roller_radius: float, sigma: float = 1.0, return_param: bool = False):
    """Roller-centre height y (mm) at cam angles ``theta``: the highest roller touching the cam."""
    theta = np.asarray(theta, dtype=float)
    pts, params = _seed(cam)
    r, e = roller_radius, offset
    best = np.empty(theta.size, dtype=int)
    value = np.empty(theta.size)
    for sl in _chunks(theta.size, len(pts)):
        x = _rot(sigma * theta[sl], pts)
        lateral = x[..., 0] - e
        with np.errstate(invalid="ignore"):
            height = np.where(np.abs(lateral) <= r, x[..., 1] + np.sqrt(np.maximum(r * r - lateral**2, 0.0)), -np.inf)
        best[sl] = np.argmax(height, axis=1)
        value[sl] = height[np.arange(height.shape[0]), best[sl]]
    if params is None:
        return value

    def residual(x, d1, d2):
        # f(t) = X_y + w, w = sqrt(r^2 - d^2), d = X_x - e: stationary where f' = 0
        d = x[:, 0] - e
        w = np.sqrt(np.maximum(r * r - d * d, 1e-300))
        f1 = d1[:, 1] - d * d1[:, 0] / w
        f2 = d2[:, 1] - (d1[:, 0] ** 2 + d * d2[:, 0]) / w - d * d * d1[:, 0] ** 2 / w**3
        return f1, f2

    t = _newton_1d(cam, sigma * theta, params[best], residual)
    x = _rot1(sigma * theta, contour_derivatives(cam, t)[0])
    y = x[:, 1] + np.sqrt(r * r - (x[:, 0] - e) ** 2)
    return (y, t) if return_param else y


def translating_flat(cam, theta, sigma: float = 1.0, return_param: bool = False):
    """Height y (mm) of a flat face normal to +y resting on the cam: max of the rotated cam's y."""
    theta = np.asarray(theta, dtype=float)
    pts, params = _seed(cam)
    best = np.empty(theta.size, dtype=int)
    value = np.empty(theta.size)
    for sl in _chunks(theta.size, len(pts)):
        y = _rot(sigma * theta[sl], pts)[..., 1]
        best[sl] = np.argmax(y, axis=1)
        value[sl] = y[np.arange(y.shape[0]), best[sl]]
    if params is None:
        return value
    t = _newton_1d(cam, sigma * theta, params[best], lambda x, d1, d2: (d1[:, 1], d2[:, 1]))
    y = _rot1(sigma * theta, contour_derivatives(cam, t)[0])[:, 1]
    return (y, t) if return_param else y


def translating_knife(cam, theta, offset: float, sigma: float = 1.0, return_param: bool = False):
    """Height y (mm) of a knife tip on the line x = offset: the highest crossing of the rotated cam."""
    theta = np.asarray(theta, dtype=float)
    pts, params = _seed(cam)
    n = len(pts)
    t0 = np.empty(theta.size)
    value = np.empty(theta.size)
    for sl in _chunks(theta.size, n):
        x = _rot(sigma * theta[sl], pts)
        a, b = x, np.roll(x, -1, axis=1)
        da, db = a[..., 0] - offset, b[..., 0] - offset
        cross = (da <= 0) & (db > 0) | (da > 0) & (db <= 0)
        with np.errstate(divide="ignore", invalid="ignore"):
            w = np.where(cross, da / (da - db), 0.0)
        y = np.where(cross, a[..., 1] + w * (b[..., 1] - a[..., 1]), -np.inf)
        k = np.argmax(y, axis=1)
        rows = np.arange(y.shape[0])
        value[sl] = y[rows, k]
        if params is not None:
            nxt = np.where(k + 1 < n, params[(k + 1) % n], cam.n_segments)
            t0[sl] = params[k] + w[rows, k] * (nxt - params[k])
    if params is None:
        return value
    t = _newton_1d(cam, sigma * theta, t0, lambda x, d1, d2: (x[:, 0] - offset, d1[:, 0]))
    y = _rot1(sigma * theta, contour_derivatives(cam, t)[0])[:, 1]
    return (y, t) if return_param else y


# --------------------------------------------------------------------------------------------
# Oscillating followers
# --------------------------------------------------------------------------------------------
def _wrap(a: np.ndarray) -> np.ndarray:
    return np.mod(a + math.pi, 2 * math.pi) - math.pi


def arm_circle_crossings(pivot, arm_length: float, radius: float) -> np.ndarray:
    """The two arm angles (rad) at which the point ``pivot + arm_length u(g)`` lies on the circle
    ``|X| = radius`` about the cam axis (law of cosines in the triangle axis-pivot-point)."""
    px, py = pivot
    d = math.hypot(px, py)
    # |X|^2 = d^2 + L^2 + 2 L (p . u) = radius^2  ->  cos(g - angle(p)) = (radius^2 - d^2 - L^2) / (2 L d)
    half = math.acos((radius**2 - d * d - arm_length**2) / (2 * arm_length * d))
    base = math.atan2(py, px)
    return np.array([base + half, base - half])


def oscillating_roller(cam, theta, pivot, arm_length: float, roller_radius: float, rest_angle: float,
                       lift_sign: float, sigma: float = 1.0, window: float = math.radians(60.0), return_param: bool = False):
    """Arm angle (rad) at cam angles ``theta``: the most lifted arm position (``lift_sign`` = the sign
    of d(arm angle) for lift) at which the roller touches the cam, within ``window`` of ``rest_angle``.
    ``roller_radius = 0`` gives a knife."""
    theta = np.asarray(theta, dtype=float)
    pts, params = _seed(cam)
    o = np.asarray(pivot, dtype=float)
    L, r = arm_length, roller_radius
    best = np.empty(theta.size, dtype=int)
    value = np.empty(theta.size)
    for sl in _chunks(theta.size, len(pts)):
        x = _rot(sigma * theta[sl], pts) - o
        dist = np.hypot(x[..., 0], x[..., 1])
        if r > 0:
            # roller centre C on |C - o| = L and |C - X| = r: g = angle(X - o) +- acos((L^2 + dist^2 - r^2) / (2 L dist))
            with np.errstate(invalid="ignore"):
                half = np.arccos(np.clip((L * L + dist * dist - r * r) / (2 * L * dist), -1.0, 1.0))
            ok = np.abs(dist - L) <= r
            base = np.arctan2(x[..., 1], x[..., 0])
            cand = np.stack([base + half, base - half])
            lift = lift_sign * _wrap(cand - rest_angle)
            lift = np.where(ok[None] & (np.abs(lift) < window), lift, -np.inf).max(axis=0)
        else:
            # knife: the polygon edges crossing the arm circle
            a, b = dist - L, np.roll(dist, -1, axis=1) - L
            cross = (a <= 0) & (b > 0) | (a > 0) & (b <= 0)
            xb = np.roll(x, -1, axis=1)
            d = xb - x
            # the edge x + w d meets the arm circle |.| = L where A w^2 + 2 B w + C = 0 (one root in [0, 1]
            # when the ends lie on both sides: |x + w d| is convex in w)
            qa = np.sum(d * d, axis=-1)
            qb = np.sum(x * d, axis=-1)
            qc = dist * dist - L * L
            with np.errstate(divide="ignore", invalid="ignore"):
                root = np.sqrt(np.maximum(qb * qb - qa * qc, 0.0))
                w1, w2 = (-qb - root) / qa, (-qb + root) / qa
            w = np.where((w1 >= -1e-12) & (w1 <= 1 + 1e-12), w1, w2)
            w = np.where(cross, np.clip(np.nan_to_num(w), 0.0, 1.0), 0.0)
            pt = x + w[..., None] * d
            g = np.arctan2(pt[..., 1], pt[..., 0])
            lift = lift_sign * _wrap(g - rest_angle)
            lift = np.where(cross & (np.abs(lift) < window), lift, -np.inf)
        best[sl] = np.argmax(lift, axis=1)
        value[sl] = rest_angle + lift_sign * lift[np.arange(lift.shape[0]), best[sl]]
    if params is None:
        return value

    def system(x, d1, d2, g):
        u = np.stack([np.cos(g), np.sin(g)], axis=-1)
        c = o + L * u
        cg = L * np.stack([-u[:, 1], u[:, 0]], axis=-1)
        diff = c - x
        jac = np.empty((g.size, 2, 2))
        if r > 0:  # |C - X|^2 = r^2 and (C - X) . X' = 0 (the contact normal passes through C)
            f = np.stack([np.sum(diff * diff, axis=1) - r * r, np.sum(diff * d1, axis=1)], axis=1)
            jac[:, 0, 0] = -2 * np.sum(diff * d1, axis=1)
            jac[:, 0, 1] = 2 * np.sum(diff * cg, axis=1)
            jac[:, 1, 0] = -np.sum(d1 * d1, axis=1) + np.sum(diff * d2, axis=1)
            jac[:, 1, 1] = np.sum(cg * d1, axis=1)
        else:  # X(t) = C(g)
            f = x - c
            jac[:, :, 0] = d1
            jac[:, :, 1] = -cg
        return f, jac

    t, g = _newton_2d(cam, sigma * theta, params[best], value.copy(), system)
    return (g, t) if return_param else g


def oscillating_flat(cam, theta, pivot, face_offset: float, rest_angle: float, lift_sign: float, sigma: float = 1.0,
                     window: float = math.radians(60.0), return_param: bool = False):
    """Angle (rad) of the face normal ``w`` (pointing away from the cam) of a flat face on the line
    ``(X - pivot) . w = -face_offset`` turning about the pivot: the most lifted position touching the cam."""
    theta = np.asarray(theta, dtype=float)
    pts, params = _seed(cam)
    o = np.asarray(pivot, dtype=float)
    f = face_offset
    best = np.empty(theta.size, dtype=int)
    value = np.empty(theta.size)
    for sl in _chunks(theta.size, len(pts)):
        x = _rot(sigma * theta[sl], pts) - o
        dist = np.hypot(x[..., 0], x[..., 1])
        # the face line passes through X where |X - o| cos(psi - angle(X - o)) = -f
        half = np.arccos(np.clip(-f / dist, -1.0, 1.0))
        base = np.arctan2(x[..., 1], x[..., 0])
        cand = np.stack([base + half, base - half])
        lift = lift_sign * _wrap(cand - rest_angle)
        lift = np.where(np.abs(lift) < window, lift, -np.inf).max(axis=0)
        best[sl] = np.argmax(lift, axis=1)
        value[sl] = rest_angle + lift_sign * lift[np.arange(lift.shape[0]), best[sl]]
    if params is None:
        return value

    def system(x, d1, d2, psi):
        w = np.stack([np.cos(psi), np.sin(psi)], axis=-1)
        jw = np.stack([-w[:, 1], w[:, 0]], axis=-1)
        fval = np.stack([np.sum((x - o) * w, axis=1) + f, np.sum(d1 * w, axis=1)], axis=1)
        jac = np.empty((psi.size, 2, 2))
        jac[:, 0, 0] = np.sum(d1 * w, axis=1)
        jac[:, 0, 1] = np.sum((x - o) * jw, axis=1)
        jac[:, 1, 0] = np.sum(d2 * w, axis=1)
        jac[:, 1, 1] = np.sum(d1 * jw, axis=1)
        return fval, jac

    t, psi = _newton_2d(cam, sigma * theta, params[best], value.copy(), system)
    return (psi, t) if return_param else psi


def polygon_distance(pts: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The distance (M,) from each point (M, 2) to the closed polygon ``pts`` (N, 2): to every
    edge, brute force in chunks."""
    a, b = pts, np.roll(pts, -1, axis=0)
    edge = b - a
    out = np.empty(len(points))
    for sl in _chunks(len(points), len(pts)):
        rel = points[sl, None, :] - a[None]
        u = np.clip(np.sum(rel * edge[None], axis=-1) / np.sum(edge * edge, axis=-1)[None], 0.0, 1.0)
        out[sl] = np.min(np.hypot(*(rel - u[..., None] * edge[None]).transpose(2, 0, 1)), axis=1)
    return out
