"""The drawn linkage's synthesis face (mechanisms.synthesis): path, motion and function
generation on any drawn topology whose closures are dyads, RRP, RPR or groups of pinned links
(class-III triads, followed by continuation), by the shared search
(linkcli.synthesis) over the population of drawings whose free joints move within their
boxes (drawn.population). Its keys: synthesis.schema."""

from __future__ import annotations

from linkcli.mechanisms.synthesis import Face

SOLVE = "linkcli.synthesis.run:solve"


class DrawnFace(Face):
    mechanism = "drawn"
    strategies = {
        "function-generation": ("linkcli.synthesis.schema:read_function", SOLVE),
        "path-generation": ("linkcli.synthesis.schema:read_path", SOLVE),
        "motion-generation": ("linkcli.synthesis.schema:read_motion", SOLVE),
    }

    def population(self, problem):
        """The drawings of a DrawnDesignProblem: its free joints within their boxes, tracing
        its target joint (path) or following its target link (motion, function)."""
        from linkcli.mechanisms.drawn.population import DrawnPopulation
        from linkcli.mechanisms.drawn.structure import analyse
        drawing = problem.drawing
        return DrawnPopulation(drawing, analyse(drawing), problem.free, dict(problem.boxes),
                               traced=(problem.joint,) if problem.joint else (),
                               followed=(problem.link,) if problem.link else ())


FACE = DrawnFace()
