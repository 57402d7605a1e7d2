"""xrdf-tools: convert, lint, diff, report on and visualize XRDF robot descriptions."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("xrdf-tools")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0+unknown"

__all__ = ["__version__"]
