"""The thesis's bottle family (§3.5.2, Fig 3.11(a)) as exact signed-distance obstacles.

An ellipse defines the base and a spline curve shapes the wall; the wall is
sampled vertically with one ellipse per height.  The thesis names 12 shape
variables ``p_1 … p_12`` without listing them; ours are (:class:`BottleParams`)

==========  ==============================================================
p1          height ``H`` [m]
p2          base semi-axis ``a0`` [m] (along the section's local x)
p3          base aspect ``b/a``
p4 … p8     wall radius scale at ``z = 0.2H … 1.0H`` (1 at ``z = 0``),
            joined by a natural cubic spline (C², smooth shoulders/waists)
p9          top aspect ``b/a`` (blended linearly from p3 up the height)
p10         twist of the ellipse axes at the top [rad] (linear in z)
p11, p12    lean: section-centre offset ``(x, y)`` at the top [m],
            quadratic in z — the non-zero lean makes an object asymmetric
==========  ==============================================================

The surface is the smooth limit of the thesis's ruled surface:
``S(θ, z) = c(z) + e^{iφ(z)} (A(z) cos θ + i B(z) sin θ) + z e_z`` written in
complex form for the horizontal components.  The closest point to a query is
found by Newton's method on ``½|S(θ, z) − x|²`` with exact first and second
derivatives, so distances and normals are exact to round-off, not to a mesh
resolution, and a call on a pad face (~10³ points) costs about a millisecond.
Only the side wall is modelled (grasps stay away from the base and the top).
"""

from __future__ import annotations

from dataclasses import astuple, dataclass

import numpy as np
from scipy.interpolate import CubicSpline

WALL_HEIGHTS = (0.0, 0.2, 0.4, 0.6, 0.8, 1.0)  # spline knots as fractions of H


@dataclass(frozen=True)
class BottleParams:
    """The 12 shape variables (see the module table); lengths in metres."""

    height: float = 0.20  # p1
    a0: float = 0.035  # p2
    aspect0: float = 0.8  # p3
    s1: float = 1.0  # p4 (z = 0.2 H)
    s2: float = 1.0  # p5
    s3: float = 1.0  # p6
    s4: float = 1.0  # p7
    s5: float = 1.0  # p8 (z = H)
    aspect1: float = 0.8  # p9
    twist: float = 0.0  # p10 [rad]
    lean_x: float = 0.0  # p11 [m]
    lean_y: float = 0.0  # p12 [m]

    def __post_init__(self) -> None:
        values = np.array(astuple(self), dtype=float)
        if not np.isfinite(values).all():
            raise ValueError(f"bottle parameters must be finite; got {self}")
        positive = ("height", "a0", "aspect0", "s1", "s2", "s3", "s4", "s5", "aspect1")
        bad = [n for n in positive if getattr(self, n) <= 0]
        if bad:
            raise ValueError(f"bottle parameters {bad} must be > 0; got {self}")

    @property
    def asymmetric(self) -> bool:
        return self.lean_x != 0.0 or self.lean_y != 0.0


class Bottle:
    """Signed distance to the bottle wall (positive outside), in the object frame
    (z up, base at z = 0); ``signed_distance(x) -> (d (N,), n (N, 3))``."""

    NEWTON_ITERATIONS = 30  # quadratic convergence: 4-6 are used from the start guess

    def __init__(self, params: BottleParams) -> None:
        self.params = p = params
        z = np.array(WALL_HEIGHTS) * p.height
        self._scale = CubicSpline(z, [1.0, p.s1, p.s2, p.s3, p.s4, p.s5], bc_type="natural")
        zz = np.linspace(0.0, p.height, 401)
        if (self.semi_axes(zz)[1] <= 0).any():
            raise ValueError(
                f"the wall spline of {p} crosses the axis (negative radius); use smaller scale changes"
            )

    # --- profile functions of z and their first two derivatives ---------------
    def semi_axes(self, z: np.ndarray, nu: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """``(A, B)`` or their ``nu``-th z-derivatives."""
        p = self.params
        H = p.height
        s = [self._scale(z, k) for k in range(nu + 1)]
        asp = p.aspect0 + (p.aspect1 - p.aspect0) * z / H
        dasp = (p.aspect1 - p.aspect0) / H
        A = p.a0 * s[nu]
        if nu == 0:
            B = A * asp
        elif nu == 1:
            B = p.a0 * (s[1] * asp + s[0] * dasp)
        else:
            B = p.a0 * (s[2] * asp + 2 * s[1] * dasp)
        return A, B

    def _centre(self, z: np.ndarray, nu: int) -> np.ndarray:
        p = self.params
        lean = complex(p.lean_x, p.lean_y)
        t = z / p.height
        return lean * (t**2, 2 * t / p.height, np.full_like(t, 2 / p.height**2))[nu]

    def _surface(self, th: np.ndarray, z: np.ndarray):
        """Horizontal position P (complex) and its derivatives in θ and z."""
        p = self.params
        A, B = self.semi_axes(z)
        A1, B1 = self.semi_axes(z, 1)
        A2, B2 = self.semi_axes(z, 2)
        phi1 = p.twist / p.height
        E = np.exp(1j * phi1 * z)
        c, s = np.cos(th), np.sin(th)
        q, q_t = A * c + 1j * B * s, -A * s + 1j * B * c
        q_z, q_tz, q_zz = A1 * c + 1j * B1 * s, -A1 * s + 1j * B1 * c, A2 * c + 1j * B2 * s
        P = self._centre(z, 0) + E * q
        P_t = E * q_t
        P_tt = -E * q
        P_z = self._centre(z, 1) + E * (1j * phi1 * q + q_z)
        P_tz = E * (1j * phi1 * q_t + q_tz)
        P_zz = self._centre(z, 2) + E * (-(phi1**2) * q + 2j * phi1 * q_z + q_zz)
        return P, P_t, P_tt, P_z, P_tz, P_zz

    def closest(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Surface parameters ``(θ, z)`` of the closest wall points to ``x`` (N, 3)."""
        x = np.asarray(x, dtype=float)
        X = x[:, 0] + 1j * x[:, 1]
        z = x[:, 2].copy()
        A, B = self.semi_axes(z)
        q = (X - self._centre(z, 0)) * np.exp(-1j * self.params.twist * z / self.params.height)
        th = np.arctan2(q.imag / B, q.real / A)
        # Newton on the section's angle stops at round-off of the bottle's size (its iterates converge
        # quadratically)
        tol = 1e-13 * self.params.height
        for _ in range(self.NEWTON_ITERATIONS):
            P, P_t, P_tt, P_z, P_tz, P_zz = self._surface(th, z)
            r, rz = P - X, z - x[:, 2]
            dot = lambda a, b: (a * np.conj(b)).real  # noqa: E731 (2D dot of complex numbers)
            g = np.stack([dot(r, P_t), dot(r, P_z) + rz])
            # Gauss-Newton part plus the curvature terms of the full Hessian
            Gtt, Gtz, Gzz = dot(P_t, P_t), dot(P_t, P_z), dot(P_z, P_z) + 1.0
            Htt, Htz, Hzz = Gtt + dot(r, P_tt), Gtz + dot(r, P_tz), Gzz + dot(r, P_zz)
            # Newton where the Hessian is positive definite, else Gauss-Newton
            ok = (Htt * Hzz - Htz**2 > 0) & (Htt > 0)
            Htt, Htz, Hzz = np.where(ok, Htt, Gtt), np.where(ok, Htz, Gtz), np.where(ok, Hzz, Gzz)
            det = Htt * Hzz - Htz**2
            dth = -(Hzz * g[0] - Htz * g[1]) / det
            dz = -(-Htz * g[0] + Htt * g[1]) / det
            # trust region: far queries (a jaw placed well outside) must not jump
            # across the bottle or off the spline's range
            dth = np.clip(dth, -0.5, 0.5)
            dz = np.clip(dz, -0.25 * self.params.a0, 0.25 * self.params.a0)
            th, z = th + dth, z + dz
            if np.max(np.abs(dz) + np.abs(dth) * self.params.a0) < tol:
                break
        return th, z

    def points_normals(self, th: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Wall points (N, 3) and outward unit normals (N, 3) at parameters (θ, z)."""
        P, P_t, _, P_z, _, _ = self._surface(th, z)
        pts = np.column_stack([P.real, P.imag, z])
        St = np.column_stack([P_t.real, P_t.imag, np.zeros_like(z)])
        Sz = np.column_stack([P_z.real, P_z.imag, np.ones_like(z)])
        n = np.cross(St, Sz)  # θ runs counter-clockwise seen from +z, so this points out
        return pts, n / np.linalg.norm(n, axis=1, keepdims=True)

    def signed_distance(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        x = np.asarray(x, dtype=float)
        pts, n = self.points_normals(*self.closest(x))
        return np.einsum("ij,ij->i", x - pts, n), n

    def section(self, z: float) -> tuple[np.ndarray, float, float, float]:
        """Centre (2,), semi-axes A, B and axis angle φ of the cross-section at height z."""
        zz = np.array([float(z)])
        A, B = self.semi_axes(zz)
        c = self._centre(zz, 0)[0]
        return (
            np.array([c.real, c.imag]),
            float(A[0]),
            float(B[0]),
            self.params.twist * float(z) / self.params.height,
        )

    def to_trimesh(self, n_theta: int = 128, n_z: int = 160):
        """Watertight triangle mesh of the wall with flat caps (for renders and export)."""
        import trimesh

        th = np.linspace(0.0, 2 * np.pi, n_theta, endpoint=False)
        zs = np.linspace(0.0, self.params.height, n_z)
        T, Z = np.meshgrid(th, zs)
        pts, _ = self.points_normals(T.ravel(), Z.ravel())
        i, j = np.meshgrid(np.arange(n_z - 1), np.arange(n_theta), indexing="ij")
        a = i * n_theta + j
        b = i * n_theta + (j + 1) % n_theta
        c, d = a + n_theta, b + n_theta
        faces = [
            np.column_stack([a.ravel(), b.ravel(), d.ravel()]),
            np.column_stack([a.ravel(), d.ravel(), c.ravel()]),
        ]
        bottom, top = len(pts), len(pts) + 1
        centres = [
            np.r_[self.section(0.0)[0], 0.0],
            np.r_[self.section(self.params.height)[0], self.params.height],
        ]
        ring = np.arange(n_theta)
        faces.append(np.column_stack([np.full(n_theta, bottom), (ring + 1) % n_theta, ring]))
        last = (n_z - 1) * n_theta
        faces.append(np.column_stack([np.full(n_theta, top), last + ring, last + (ring + 1) % n_theta]))
        return trimesh.Trimesh(np.vstack([pts, centres]), np.vstack(faces), process=False)


class Posed:
    """An obstacle seen from the pad frame: ``x_object = R x_pad + t``."""

    def __init__(self, obstacle, R: np.ndarray, t: np.ndarray) -> None:
        self.obstacle, self.R, self.t = obstacle, np.asarray(R, float), np.asarray(t, float)

    def signed_distance(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        d, n = self.obstacle.signed_distance(self.to_object(x))
        return d, n @ self.R

    def to_object(self, x: np.ndarray) -> np.ndarray:
        return np.asarray(x, float) @ self.R.T + self.t


def grasp_pose(
    bottle: Bottle, height: float, approach: float, face_xy: np.ndarray, pad_thickness: float
) -> Posed:
    """Pad frame of a jaw at ``height`` [m] approaching horizontally at angle ``approach``
    [rad, from the section's major axis] towards the section centre, placed so that the
    undeformed pad face (nodes ``face_xy`` (n, 2) at z = ``pad_thickness``) just touches
    the wall (min gap 0): jaw displacements are then measured from first touch.

    Pad axes in the object frame: z = approach direction (into the object), y = up
    (the pad's long side is vertical, as for a side grasp of a standing bottle).
    """
    centre, A, B, phi = bottle.section(height)
    ang = phi + approach
    out = np.array([np.cos(ang), np.sin(ang), 0.0])  # from the centre towards the jaw
    # a mesh offers the side the jaw can touch: a thin shell's far wall is not pressed
    target = bottle.one_sided(out) if hasattr(bottle, "one_sided") else bottle
    ez, ey = -out, np.array([0.0, 0.0, 1.0])
    R = np.column_stack([np.cross(ey, ez), ey, ez])
    X = np.column_stack([face_xy, np.full(face_xy.shape[0], pad_thickness)])
    offset = 1.5 * max(A, B) + pad_thickness  # start outside, then close the gap
    origin = np.r_[centre, height] + out * offset
    for _ in range(50):
        d, _ = Posed(target, R, origin).signed_distance(X)
        gap = float(d.min())
        origin = origin - out * gap
        # the ray already touches the surface to round-off (metres: 1e-12 m)
        if abs(gap) < 1e-12:
            break
    return Posed(target, R, origin)


def bottle_family(n: int = 24, n_asymmetric: int = 8, seed: int = 0) -> list[BottleParams]:
    """``n`` bottles with random shape variables (seeded); the last ``n_asymmetric``
    lean, the others are upright (symmetric about their axis)."""
    if not (1 <= n and 0 <= n_asymmetric <= n):
        raise ValueError(f"need n >= 1 and 0 <= n_asymmetric <= n; got n={n}, n_asymmetric={n_asymmetric}")
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        H = rng.uniform(0.15, 0.25)
        lean = len(out) >= n - n_asymmetric
        p = BottleParams(
            height=H,
            a0=rng.uniform(0.025, 0.045),
            aspect0=rng.uniform(0.55, 1.0),
            s1=rng.uniform(0.8, 1.25),
            s2=rng.uniform(0.7, 1.3),
            s3=rng.uniform(0.6, 1.3),
            s4=rng.uniform(0.5, 1.2),
            s5=rng.uniform(0.4, 1.0),
            aspect1=rng.uniform(0.55, 1.0),
            twist=rng.uniform(-np.pi / 4, np.pi / 4),
            lean_x=rng.uniform(-0.15, 0.15) * H * lean,
            lean_y=rng.uniform(-0.1, 0.1) * H * lean,
        )
        try:
            b = Bottle(p)
        except ValueError:
            continue
        # a graspable wall: radius >= 12 mm between 20% and 80% of the height
        zz = np.linspace(0.2 * H, 0.8 * H, 61)
        if b.semi_axes(zz)[1].min() >= 0.012 and b.semi_axes(zz)[0].max() <= 0.07:
            out.append(p)
    return out
