%SUB.nc
[REFUSED: a subprogram call (L"name"); the subprogram after ENDE is not run unless called]
BEARBEITUNG
N1 G0 X20 Z2
N2 L"GROOVE" V1
ENDE
UNTERPROGRAMM "GROOVE"
N100 G1 X18 F0.1
RETURN
