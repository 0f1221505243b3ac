"""Kinematics per mechanism (four-bar, slider-crank), vectorized over angles and populations."""
