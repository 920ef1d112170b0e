%FUZZ.nc
[Found by the fuzz harness: a feed per minute while G96 is in force with a limit. SINUMERIK]
[writes G961 S100 (G96 with a feed per minute), under the LIMS=1000 written before, which]
[stays in force; the test side's translation dropped the limit there.]
[Hand-derived: G97 500 rpm; G0 D130 Z20; G96 100 m/min up to 1000 rpm; F 200 mm/min; G0 D10 Z0.]
BEARBEITUNG
N1 G97 S500 M3
N2 G95 G0 X130 Z20 F0.2
N3 G26 S1000
N4 G96 S100 M3
N5 G94 F200
N6 G0 X10 Z0
N7 M5
N8 M30
ENDE
