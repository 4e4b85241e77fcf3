"""CI validation of product lines: products derived in workers or on a Dask cluster, every
artifact checked, JUnit reports (docs/ci.md)."""
