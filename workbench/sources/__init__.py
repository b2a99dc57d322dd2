"""Profile sources: every way to make a :class:`~workbench.profile.ContactProfile`.

The first stage of the data flow (profile source -> profile -> wrenches -> limit surface ->
contact model -> grasp metric); everything downstream takes a ``ContactProfile`` and does
not ask where it came from.  One source per module:

surfaces.py         parametric surfaces ``σ(u, v)`` with a pressure, their adaptive
                    quadrature (continuous 6DFW, Eqs. 3.3–3.5) and triangle meshes
                    (:func:`~.surfaces.mesh_profile`)
surface_catalog.py  the thesis's surfaces S1–S6 (Table 3.1) and Example 3.2.5
reach.py            REACH-style pad ∩ mesh with Winkler pressure, one jaw or both jaws of
                    a grasp (§2.3.1.3, §4.1.4.1)
scenes.py           the elliptic-cylinder grasp with the power-law pressure of Eq. 4.3
fem_jaw.py          the FEM adapter: the compliant pad of ``workbench.fem`` pressed on an
                    object mesh to the gripper's reading (§3.5.2, §4.3.2.1)
jaws.py             what the jaw sources share: the grasp dict, the jaw frame, scaling to
                    the force-sensor reading (§4.1.3.2) and the check a jaw's profile of
                    any source passes before grasp analysis uses it

Meshes with a pressure per face enter through the profile's own constructors
(``ContactProfile.from_mesh``, ``from_meshio``, ``from_trimesh``); an FEM solution on
analytic obstacles through ``workbench.fem.press(...).profile(delta)``.

Nothing is imported here: ``import workbench.sources.<module>`` loads one source (the FEM
one pulls in scikit-fem) without the others.
"""
