"""The grasp tests' shared scene: two antipodal jaws at ±A on the x axis, each pressing
with F, friction coefficient MU (tests/test_contacts.py, test_resistance.py, test_gws.py,
test_robust.py, test_exact.py)."""

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
