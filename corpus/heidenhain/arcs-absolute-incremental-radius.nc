%ARCS.nc
[Arcs in the three forms: G2/G3 with the centre from the start (I a radius value), G12/G13 with]
[the absolute centre (I the centre's X as a radius), and R (the arc up to half a circle).]
[Its sidecar profile: G2/G12 turn as LinuxCNC's G2 (arc_direction = "iso").]
[Hand-derived: from D20 Z0, G3 to D30 Z-5 around D20 Z-5 (r5: I0 K-5 from the start);]
[G1 to Z-10; G12 to D30 Z-20 around D30 Z-15 (I15 K-15), a half circle through D20 Z-15;]
[G1 to Z-25; G2 R5 to D40 Z-30: the centre 5 mm from both ends, clockwise: D40 Z-25.]
BEARBEITUNG
N10 G97 S600 M3
N20 G0 X20 Z2
N30 G95 G1 Z0 F0.1
N40 G3 X30 Z-5 I0 K-5
N50 G1 Z-10
N60 G12 X30 Z-20 I15 K-15
N70 G1 Z-25
N80 G2 X40 Z-30 R5
N90 G0 X50 Z50
N100 M5
ENDE
