"""pmplan's version, the one source (``pyproject.toml`` reads it; :data:`pmplan.__version__`)."""

__version__ = "0.1.0"
