"""Analyses of a given linkage (loads, ...): pure numpy, vectorized over the motion's rows."""
