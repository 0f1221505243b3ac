"""The report sections every linkage shares: class, transmission, motion, kinematics,
error and tolerance (generic over mechanisms)."""
