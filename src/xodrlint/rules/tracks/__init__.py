"""The track links rule pack (TR): `road/link` between roads with a rail or tram lane."""
