"""What drawings share: the style, figure header and a linkage drawn to scale from its
skeleton (`common`), the load cycle (`forces`) and the strength (`strength`) panels. It knows
no mechanism and no problem type: each mechanism draws itself in its home's `plot` module, and
each problem type in `linkcli.types.<type>.plot`, exposing `NEEDS` (the report sections it
draws from) and `draw(fig, result)`.

Every module imports matplotlib only through the `Figure` it is handed, so importing
this package never imports matplotlib; `linkcli.plot` does that, on demand.
"""
