"""House rules for OpenDRIVE rail networks: an example of a third-party xodrlint pack.

Three rules a railway operator might keep beside the standard's: switch ids that fit the
interlocking's 32-bit field (HR001), station names in the house style (HR002), and
platforms long enough for the operator's trains (HR003). xodrlint finds them through the
``house`` entry point of the ``xodrlint.rules`` group, which names this package: every
rule defined in its modules is registered.
"""

#: The rule API this pack is written for (xodrlint.rules.API_VERSION when it was made):
#: an xodrlint of another major version, or of an older minor one, does not load it and
#: says so once, instead of running rules that may misread the model.
XODRLINT_RULE_API = (1, 3)  # 1.3: HR002 has a fix
