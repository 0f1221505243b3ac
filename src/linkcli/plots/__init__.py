"""What drawings share: the style and figure header (`common`) and the angle-function
picture of precision positions and function generation (`angle_function`). Each problem
type draws in `linkcli.types.<type>.plot`, exposing `NEEDS` (the report sections it draws
from) and `draw(fig, report, problem)`.

Every module imports matplotlib only through the `Figure` it is handed, so importing
this package never imports matplotlib; `linkcli.plot` does that, on demand.
"""
