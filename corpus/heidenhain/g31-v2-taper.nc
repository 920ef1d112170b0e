%G31V2.nc
[G31 V2 on a taper, under the sidecar profile's model (g31_clearance = 0.5). The contour runs]
[from D20 Z0 to D22 Z-20; B0 P0 (on a taper the thread's passes run on the contour itself).]
[V2 with I0.3, U1.0: 1.0 = 3 x 0.3 + 0.1, so the remainder 0.1 is cut first, then 0.3, 0.3,]
[the last 0.3 split into 0.15, 0.075, 0.0375, 0.0375: depths 0.1, 0.4, 0.7, 0.85, 0.925,]
[0.9625, 1.0. Hand-derived moves: G0 X23 Z0 (D22 + 2 x 0.5); each pass G0 X(20 - 2d) Z0,]
[G33 X(22 - 2d) Z-20 at lead 1.5, G0 X23, G0 Z0: from X19.8, 19.2, 18.6, 18.3, 18.15, 18.075,]
[18 to X21.8, 21.2, 20.6, 20.3, 20.15, 20.075, 20.]
BEARBEITUNG
N10 T3 G97 S800 M3
N20 G31 F1.5 U1 B0 P0 I0.3 V2
N30 G0 X20 Z0
N40 G1 X22 Z-20
N50 G80
N60 G0 X100 Z50
N70 M30
ENDE
