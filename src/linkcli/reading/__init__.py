"""Problem files and result files, read: what their tables mean. Above the mechanism homes (it
asks each home's schema, `mechanisms.schema.Schema`, for its keys and names) and below the
problem types (each type's `schema.py` reads its own tables with these parts).

`load` (a file -> its type's frozen problem, every error located), `meta` (the tables every
problem shares: title, [units], [solver], [reference], [report], [tolerance]), `linkage` (any
mechanism's [linkage]), `loads`, `strength`, `tolerance_keys`, `tolerance_lengths`,
`robust_keys` (the optional tables), and the result files `analyze` reads back (`result_file`,
`result_check`, `result_keys`, `result_motion`). Pure Python: `check` reads a file without numpy.
"""
