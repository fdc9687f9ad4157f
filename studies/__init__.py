"""The studies: each run as a script (``python studies/X.py``), and importable as ``studies.X`` (by one another and
by the tests)."""
