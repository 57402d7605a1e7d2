"""CLI command modules: one per subcommand. Only these modules (and ``cli/__init__.py``) print or
exit.

Heavy libraries (yourdfpy, trimesh, rerun, mcap, matplotlib) are imported inside the command
functions, never at module level, so ``xrdf lint`` starts fast. ``xrdf lint`` itself usually
runs without typer: :mod:`.lint_core` holds its body and reads its arguments, :mod:`.core` what
the commands share that needs no typer (:mod:`.common` re-exports it), and :mod:`.app` is the
Typer app.
"""
