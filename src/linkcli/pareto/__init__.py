"""Trade-offs as Pareto fronts (`[objective] minimize = [...]`, docs/pareto.md).

`objectives` measures a finished design (through the mechanism protocol), `scalarized` is one
epsilon-constraint problem, `front` the sweep's steps (anchors, levels, points, rows),
`hypervolume` the hypervolume and the knee, `run` a type's front start to end and its
`front` section, `spread` where the levels are solved, `space` the hook a synthesis type
gives (its `types/<type>/pareto.py`), `plot` the front's drawing. A type calls
`run.solve_front(problem, space, solution)`; nothing here asks which type or mechanism it holds.
"""
