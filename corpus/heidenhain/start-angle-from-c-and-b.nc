%START_ANGLE.nc
[G33's start angle: "at the end of the run-in path B the spindle is at the starting angle C".]
[With its sidecar profile (C counts with the spindle), the spindle angle at the pass's start is]
[C less the turn over B: C90 after B0.5 at lead 2 is 90 - 360*0.5/2 = 0 deg; C120 after B3 at]
[lead 2 (one and a half turns) is 120 - 540 = -420 = 300 deg; C0 after B2 is 0 deg.]
[Hand-derived: three passes D19 Z3 to Z-16 at lead 2, starting at 0, 300 and 0 deg.]
BEARBEITUNG
N1 G97 S600 M3
N2 G0 X19 Z3
N3 G33 X19 Z-16 F2 B0.5 P2 C90 H0
N4 G0 X22
N5 Z3
N6 X19
N7 G33 X19 Z-16 F2 B3 P2 C120
N8 G0 X22
N9 Z3
N10 X19
N11 G33 X19 Z-16 F2 B2 P2
N12 G0 X22
ENDE
