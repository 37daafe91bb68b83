"""One module per language, named by its code (``en``, ``es``), each defining ``STRINGS``.

A new language is a new module here holding the same keys and ``{placeholders}`` as ``en``; no
other code changes.
"""
