"""Reference solutions for the validation cases, computed here from their
closed forms or by shooting with a library ODE integrator (scipy).

Cantilever of length L along +x, clamped at the origin, with a dead end force
P = (Px, Py) and an end moment M. The internal force is P everywhere; with the
section's axis t = (cos theta, sin theta) and normal n = (-sin theta, cos
theta) the axial strain is eps = P.t / EA and the shear strain gamma = P.n /
GA (the extensible elastica of the discrete chain has GA = inf; the Reissner
rod FEM its shear stiffness, the Kirchhoff variant its penalty). Unknown: the
moment at the clamp m(0); integrate
    r' = (1 + eps) t + gamma n,
    theta' = m / EI,           m' = -(r' x P)_z
from s = 0 to L and solve m(L) = M by Brent's method on a bracket that holds
the branch connected to the unloaded rod (continuation in the load).
"""
import math

from scipy.integrate import solve_ivp
from scipy.optimize import brentq


def _integrate(m0, L, EA, EI, P, GA=math.inf, dense=False):
    return solve_ivp(lambda _s, u: _rhs(u, EA, EI, P, GA), (0.0, L), [0.0, 0.0, 0.0, m0], method="DOP853",
                     rtol=1e-13, atol=1e-14, dense_output=dense)


def cantilever(L, EA, EI, P=(0.0, 0.0), M=0.0, GA=math.inf, steps=20):
    """Tip (x, y, rotation) of the loaded cantilever. The load is raised in
    `steps` increments; each solve brackets m(0) around the previous one."""
    m0 = 0.0
    for k in range(1, steps + 1):
        f = k / steps
        Pk = (f * P[0], f * P[1])
        Mk = f * M

        def miss(m):
            return _integrate(m, L, EA, EI, Pk, GA).y[3, -1] - Mk

        scale = EI / L + math.hypot(*Pk) * L + abs(Mk)
        width = 0.05 * scale
        lo, hi = m0 - width, m0 + width
        grow = 0
        while miss(lo) * miss(hi) > 0.0:
            width *= 2.0
            lo, hi = m0 - width, m0 + width
            grow += 1
            if grow > 20:
                raise RuntimeError("no bracket for m(0)")
        m0 = brentq(miss, lo, hi, xtol=1e-15 * scale, rtol=1e-15, maxiter=200)
    sol = _integrate(m0, L, EA, EI, P, GA)
    x, y, th, _ = sol.y[:, -1]
    return float(x), float(y), float(th)


def rolled_up(L, EI, M):
    """Exact end-moment cantilever (no axial force, so no stretch): a circular
    arc of radius EI/M."""
    rho = EI / M
    th = L / rho
    return rho * math.sin(th), rho * (1.0 - math.cos(th)), th


def buckled_cantilever(L, EA, EI, P, eps=0.0, GA=math.inf, n_scan=400):
    """Half of a pinned-pinned rod of length 2L under the axial load P: by
    symmetry a cantilever of length L clamped at mid-span, with the dead end
    force (-P, eps) (eps: a transverse imperfection, as the models need to
    leave the straight state). Shoots backwards from the free end on its
    rotation alpha (m = 0 there) until the clamp's angle is zero; of the
    roots, the stable branch biased by eps is the one of largest alpha with
    the sign of eps (eps = 0: alpha > 0). Returns the free end (x, y) relative
    to the clamp and alpha."""
    F = (-P, eps)

    def clamp_angle(alpha):
        sol = solve_ivp(lambda s, u: _rhs(u, EA, EI, F, GA), (L, 0.0), [0.0, 0.0, alpha, 0.0], method="DOP853",
                        rtol=1e-13, atol=1e-14)
        return sol.y[2, -1], sol.y[:, -1]

    sign = -1.0 if eps < 0 else 1.0
    grid = [sign * math.pi * (1.0 - i / n_scan) for i in range(n_scan)]  # from +-pi towards 0
    prev_a, prev_f = grid[0], clamp_angle(grid[0])[0]
    for a in grid[1:]:
        f = clamp_angle(a)[0]
        if prev_f * f <= 0.0:
            alpha = brentq(lambda x: clamp_angle(x)[0], min(a, prev_a), max(a, prev_a), xtol=1e-15, rtol=1e-15,
                           maxiter=200)
            r0 = clamp_angle(alpha)[1]
            return float(-r0[0]), float(-r0[1]), float(alpha)
        prev_a, prev_f = a, f
    raise RuntimeError("no buckled solution: below the critical load?")


def _rhs(u, EA, EI, F, GA):
    _x, _y, th, m = u
    px, py = F
    c, s = math.cos(th), math.sin(th)
    stretch = 1.0 + (px * c + py * s) / EA
    shear = (-px * s + py * c) / GA
    dx, dy = stretch * c - shear * s, stretch * s + shear * c
    return [dx, dy, m / EI, -(dx * py - dy * px)]


def elliptic_buckling(alpha):
    """Inextensible pinned-pinned elastica of length Lp with end slope alpha
    (k = sin(alpha/2)): P/P_cr = (2K/pi)^2, end shortening / Lp = 2 - 2E/K,
    mid-span deflection / Lp = k/K (K, E complete elliptic integrals of
    parameter k^2)."""
    from scipy.special import ellipe, ellipk
    k = math.sin(alpha / 2.0)
    K, E = ellipk(k * k), ellipe(k * k)
    return (2.0 * K / math.pi) ** 2, 2.0 - 2.0 * E / K, k / K


if __name__ == "__main__":
    # Inextensible check against the classical elastica numbers (stiff EA).
    for load in (1, 2, 5, 10):
        x, y, th = cantilever(1.0, 1e12, 1.0, (0.0, -load))
        print(f"PL^2/EI = {load:2d}: 1 - x/L = {1 - x:.5f}, -y/L = {-y:.5f}, rotation = {-th:.5f}")
