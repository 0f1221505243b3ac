"""The report sections every linkage shares: class, transmission, motion, kinematics,
error, tolerance and loads (generic over mechanisms)."""
