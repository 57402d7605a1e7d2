"""CLI command modules: one per subcommand. Only these modules (and ``cli.py``) print or exit.

Heavy libraries (yourdfpy, trimesh, rerun, mcap, matplotlib) are imported inside the command
functions, never at module level, so ``xrdf lint`` starts fast.
"""
