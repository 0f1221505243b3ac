"""Any planar linkage, drawn (`[linkage] mechanism = "drawn"`): docs/drawn.md."""
