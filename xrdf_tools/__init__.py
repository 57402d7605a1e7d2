"""xrdf-tools: convert, lint, diff, report on and visualize XRDF robot descriptions."""

#: The one place the version is written (pyproject.toml reads it from here); not looked up
#: through importlib.metadata, which costs every command ~30 ms at start-up.
__version__ = "0.1.0"

__all__ = ["__version__"]
