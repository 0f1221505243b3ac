"""`--dxf FILE.dxf`: a solved problem's design for CAD (ezdxf), drawn from the same Scene
as the animation (linkcli.animate.scene): `dxf` writes it, `outline` draws a link's outline
from its width.
"""
