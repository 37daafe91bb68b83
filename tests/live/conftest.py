"""Every live test runs on loopback in a DDS domain of its own: tests/conftest.py sets it up for
every test process (:func:`live_graph.domain`)."""
