"""A rule pack that misbehaves in every way a plugin can: used only by the tests
(tests/config/test_hostile_plugins.py), never installed."""
