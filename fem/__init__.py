"""scikit-fem contact of compliant pads -> ContactProfile (issue 4; not yet implemented).

This package is reserved by the repository layout; it knows nothing of friction.
"""
