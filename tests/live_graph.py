"""What the live tests share: this process's DDS domain and how long to wait for the graph."""

from __future__ import annotations

import os

#: This test process's domain (1..232); another process's tests take another one.
DOMAIN = 1 + os.getpid() % 232
#: How long a test waits for discovery or a message before it fails (s).
PATIENCE = 20.0
