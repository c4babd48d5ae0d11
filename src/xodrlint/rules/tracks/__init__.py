"""The track network rule pack (TR): roads with a rail or tram lane ("tracks"), their links,
lane links, joints, plan view and vertical and lateral profiles."""
