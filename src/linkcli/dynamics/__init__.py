"""Forward dynamics of a one-drive linkage (docs/dynamics.md): force elements, the equation of
motion from the kinematic coefficients, its integration, the energy balance, the flywheel by
the energy method, and balancing.

Shared code: it holds a mechanism's home (`linkcli.mechanisms.of`) and calls its protocol
(`body_graph`, `coefficients`, `counterweights`); it never asks which mechanism it holds.

    model        the validated [springs], [dampers], [dynamics] (pure Python: `check`)
    bodies       points, centres, inertia and generalized forces from the coefficients
    elements     springs, dampers, the drive: forces and energies
    tables       the equation's coefficients tabulated over the drive's range (splines)
    motion       the equation of motion M q'' + M' q'^2 / 2 = Q and its integration
    body_forces  pin forces, guide forces and pin friction (Newton-Euler of every body)
    history      the report's rows at the output times, all at once
    flywheel     steady running: speed fluctuation and the flywheel by the energy method
    balance      shaking force and moment; counterweights
    sections     the report sections
"""
