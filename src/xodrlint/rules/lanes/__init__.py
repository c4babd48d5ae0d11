"""The rail lanes rule pack (RL): lanes of type `rail` and `tram`."""
