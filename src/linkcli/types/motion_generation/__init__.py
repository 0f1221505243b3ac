"""Motion generation (rigid-body guidance): poses, dyads, Burmester theory, assembly of
four-bars from dyads with their defects, and least squares for many poses.

Internal convention: a pose is (x, y, angle) with the angle in RADIANS; the integrator
converts file units. A dyad is (G, M): ground pivot G in the global frame, moving pivot M
in the body frame.
"""
