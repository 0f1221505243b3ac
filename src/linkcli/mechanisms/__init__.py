"""The kinematics of each mechanism, vectorized over angles (today the four-bar)."""
