%SHAFT_1.nc
[A program with the sections a DIN program may hold: the program head and the turret table]
[describe and move nothing (passed over with a warning each, HEIR010); the machining section]
[is read; Xi/Zi are increments, Xi of the diameter. N 13 with a space, as the manuals print it.]
[Hand-derived: T3; G96 S180 limited to 2500 rpm by G26; G0 D40 Z2; G1 Z-20 at 0.25 mm/rev;]
[Xi4 to D44; Zi-10 to Z-30; G0 Xi6 to D50; G4 2.5 s; G0 Z50; M30.]
PROGRAMMKOPF
#EINHEIT METRISCH
REVOLVER
T3 ID"342-300.1"
BEARBEITUNG
N 1 T3
N 2 G26 S2500
N 3 G96 S180 M4
N 4 G0 X40 Z2 M8
N 5 G95 G1 Z-20 F0.25
N 6 Xi4
N 7 Zi-10
N 8 G0 Xi6
N 9 G4 F2.5
N 10 G0 Z50 M9
N 11 M30
ENDE
