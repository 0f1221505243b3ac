"""Engineering standards as data (pure Python, no numpy): ISO 286 limits and fits
(`iso286`), ISO 2768-1 general tolerances (`iso2768`). `linkcli check` reads them."""
