"""Socially-aware robot navigation with PaCcET multi-objective trajectory selection."""

__version__ = "0.1.0"
