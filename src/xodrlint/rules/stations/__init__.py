"""The stations rule pack (ST): `station`, `platform` and `segment`."""
