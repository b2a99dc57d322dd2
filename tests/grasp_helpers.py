"""The grasp tests' shared scene: two antipodal jaws at ±A on the x axis, each pressing
with F, friction coefficient MU (tests/test_contacts.py, test_resistance.py, test_gws.py,
test_robust.py, test_exact.py); and a synthetic measured stiffness map on a cylinder
(test_stiffness_map.py, test_work.py)."""

import numpy as np

from workbench.grasp import point_contact, soft_point_contact

MU, F, A = 0.5, 10.0, 0.03


def antipodal(kind="inner", n=64, soft=None):
    if soft is None:
        return [
            point_contact([A, 0, 0], [1, 0, 0], F, n_edges=n, kind=kind),
            point_contact([-A, 0, 0], [-1, 0, 0], F, n_edges=n, kind=kind),
        ]
    return [
        soft_point_contact([A, 0, 0], [1, 0, 0], F, soft, n_edges=n, kind=kind),
        soft_point_contact([-A, 0, 0], [-1, 0, 0], F, soft, n_edges=n, kind=kind),
    ]


# --- a synthetic measured stiffness map (tests/test_stiffness_map.py, test_work.py) ----------

R_CYL, H_CYL = 0.04, 0.10  # cylinder radius and height [m]


def stiffness_field(P):
    """A smooth stiffness field on a cylinder [N/m], symmetric under θ -> θ + π (so
    both jaws of an antipodal grasp carry one value, as in the measured maps)."""
    th, z = np.arctan2(P[:, 1], P[:, 0]), P[:, 2]
    return np.exp(np.log(1500.0) + 0.6 * np.cos(2 * th) + 1.2 * (z / H_CYL - 0.5) ** 2)


def measured_grid(nt: int, nz: int):
    """(2n, 3) antipodal jaw points on the cylinder (i and i + n one grasp) and values."""
    th = np.linspace(0, np.pi, nt, endpoint=False) + 0.1
    z = np.linspace(0.1 * H_CYL, 0.9 * H_CYL, nz)
    T, Z = np.meshgrid(th, z)
    a = np.column_stack([R_CYL * np.cos(T.ravel()), R_CYL * np.sin(T.ravel()), Z.ravel()])
    P = np.vstack([a, a * [-1, -1, 1]])
    return P, stiffness_field(P)
