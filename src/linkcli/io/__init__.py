"""What knows no mechanism and no problem type: the TOML reader and its guards (`reader`,
`safe_read`, `huge_numbers`, `header_lines`, `nesting`, `misplaced_keys`, `link_names`), the
values every table shares (`bounds`, `quantities`, `joints`), terminal text, and the output
writers (`export`: JSON/TOML with deterministic rounding; `csv_tables`; `tables`: the table
layouts a type may ask of the report; `output_guard`)."""
