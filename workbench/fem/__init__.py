"""scikit-fem contact of compliant pads -> ``workbench.ContactProfile`` (thesis §3.5.2).

A rigid jaw with a bonded silicone layer (``pad``) presses into rigid obstacles
(``obstacles``: plane, sphere, cylinder, triangle meshes; ``bottle``: the
12-parameter bottle family) at three fidelities behind one interface
(``fidelity.press``): condensed linear, full-mesh linear, neo-Hookean.
``extract.extract_profile`` turns a solution into a contact profile; in one line,
``press(geometry, material, obstacle, [delta]).profile(delta)``.  This package
knows nothing of friction or grasps and imports only the core of ``workbench``; the pad
as a jaw's profile source on an object mesh is ``workbench.sources.fem_jaw``.
"""

from .fidelity import FIDELITIES, Pressed, press

__all__ = ["FIDELITIES", "Pressed", "press"]
