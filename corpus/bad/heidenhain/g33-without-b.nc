%G33_WITHOUT_B.nc
[REFUSED: a G33 without B, as the vendor's own example writes it (MP620 User's Manual p.278):]
[the spindle is at C at the end of the run-in B, whose default is a machine parameter.]
BEARBEITUNG
N1 T5 G97 S1100 M3
N2 G0 X101.84 Z5
N3 G33 X120 Z-80 F1.5
N4 G0 X144
ENDE
