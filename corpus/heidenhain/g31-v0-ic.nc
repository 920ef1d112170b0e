%G31IC.nc
[G31 under ncthread's model (README, "HEIDENHAIN G31"), declared by the sidecar profile]
[(g31_clearance = 1.0). An M20x2 thread: crest D20, depth U1.2 per side, V0 with IC4: the cuts]
[keep the chip cross-section, depth 1.2*sqrt(n/4) = 0.6, 0.8485, 1.0392, 1.2. B4 and P2 extend]
[the contour (Z0 to Z-30) to Z4 and Z-32; Q1 adds one idle pass at the full depth.]
[Hand-derived moves: G0 X22 Z4 (the start point: D20 + 2 x 1.0, at Z0 + B); then each pass]
[G0 X(20 - 2d) Z4, G33 to Z-32 at lead 2, G0 X22, G0 Z4, at X18.8, 18.303, 17.9216, 17.6 and]
[17.6 again; the cycle ends at the start point, then N70 moves on.]
BEARBEITUNG
N10 T9 G97 S1000 M3
N20 G0 X40 Z10
N30 G31 F2 U1.2 B4 P2 IC4 V0 Q1 [M20x2]
N40 G0 X20 Z0
N50 G1 Z-30
N60 G80
N70 G0 X110 Z20
N80 M30
ENDE
