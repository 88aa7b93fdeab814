$$ a CL file that holds only comments
PARTNO/NOTHING
FINI
