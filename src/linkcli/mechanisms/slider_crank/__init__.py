"""The offset slider-crank: its home (kinematics, sections, loads, tolerance model, drawing)."""
