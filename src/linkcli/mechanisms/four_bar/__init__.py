"""The planar four-bar: its home (kinematics, sections, loads, tolerance model, drawing)."""
