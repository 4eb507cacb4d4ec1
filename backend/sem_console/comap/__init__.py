"""CoMap over IMC: the codec (messages.py, codec.py), the UDP node (transport.py), the console's C2
(c2.py). The simulator's vehicle side is sim/comap_vehicle.py."""
