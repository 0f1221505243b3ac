"""Files in and out: the TOML reader and its line map, problem and result files, JSON/TOML
export and the rich report (the only module that imports rich)."""
