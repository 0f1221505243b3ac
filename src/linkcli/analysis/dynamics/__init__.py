"""Forward dynamics of a linkage (docs/dynamics.md): force elements, the equation of motion from
the kinematic coefficients, its integration, the energy balance, the flywheel by the energy
method, and balancing (one drive); the same run for a linkage of several drives (the five-bar).

Shared code: it holds a mechanism's home (`linkcli.mechanisms.of`) and calls its protocol
(`body_graph`, `coefficients`, `counterweights`); it never asks which mechanism it holds.

    model        the validated [springs], [dampers], [dynamics] (pure Python: `check`)
    bodies       points, centres, the generalized inertia and potential from the coefficients
    elements     springs, dampers, constant couples and the drive: laws, forces, energies
    tables       the equation's functions tabulated over the drive's range (quintic splines)
    system       the equation of motion of one linkage: exact functions and their tables
    motion       its integration (solve_ivp), events, restarts at a table law's rows
    stepper      scipy's DOP853 with its sums free of the machine's BLAS
    friction     pin and guide friction in the integrator (tabulated unit responses)
    body_forces  pin forces, guide forces and friction: Newton-Euler of every body, all rows
    history      the report's rows at the output times, all at once
    flywheel     steady running: speed fluctuation and the flywheel by the energy method
    balance      shaking force and moment; counterweights
    sections     the report sections; layout: their table view
    several      the equation of motion of several drives (M q'' + h = Q, k x k), exact at every step
    several_rows       the same equation and every pin's force over the history's rows (numpy)
    several_motion     its integration: motion's settings and segments, events per drive
    several_sections   its report sections (simulation, history, events, energy per drive)
"""
