"""quick-return: crank-rockers and slider-cranks designed by time ratio K and swing or stroke.

family.py is the public numerical core (families, best member, window miss); geometry.py the
closed-form construction, transmission.py the worst transmission angle, maximize.py the
one-dimensional max-min search, simulate.py the recomputation of K and swing/stroke.
"""
