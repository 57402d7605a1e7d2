"""One module per lint rule; each defines ``RULE`` and its docstring is the documentation."""
