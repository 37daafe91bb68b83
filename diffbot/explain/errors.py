"""The error the explanations raise for a request they cannot serve."""

from __future__ import annotations

from diffbot.errors import DiffbotError

__all__ = ["ExplainError"]


class ExplainError(DiffbotError, ValueError):
    """An unknown language or output format, or a language catalogue that lacks strings."""
