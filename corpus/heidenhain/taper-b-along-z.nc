%TAPER.nc
[A taper thread (1:16 on the diameter, as a pipe thread) with its sidecar profile: the run-in B]
[is measured along Z (b_along = "z"), so the spindle is at C one lead after the start: C0 at]
[B = F is the start angle 0. Hand-derived: from D20 Z2 to D21.25 Z-18 (a radius rise of 0.625]
[over 20 mm along Z), lead 1.814 along Z, starting at 0 deg.]
BEARBEITUNG
N10 G97 S500 M3
N20 G0 X20 Z2
N30 G33 X21.25 Z-18 F1.814 B1.814 P1.814 C0 H0
N40 G0 X26
N50 Z2
N60 M5
ENDE
