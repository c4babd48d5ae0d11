"""The partner switches rule pack (PT): `switch/partner`."""
