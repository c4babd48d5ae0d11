"""The switches rule pack (SW): `road/railroad/switch` with its `mainTrack` and `sideTrack`."""
