#!/usr/bin/env python3
"""Splits models/armadillo/statespace.csv (Time, To, Qh, I_sol, xi) into the two files the house
models read, dropping the last row as pySIP's worked example does (179 rows): inputs.csv
(time, To degC, Qh W) for table() and indoor.csv (time, xi degC) as the case's data.
Usage: armadillo_csv.py STATESPACE.csv OUT_FOLDER"""
import csv, os, sys

rows = list(csv.DictReader(open(sys.argv[1])))[:-1]
out = sys.argv[2]
with open(os.path.join(out, "inputs.csv"), "w") as f:
    f.write("time,To,Qh\n")
    for r in rows:
        f.write("%s,%s,%s\n" % (r["Time"], r["To"], r["Qh"]))
with open(os.path.join(out, "indoor.csv"), "w") as f:
    f.write("time,xi\n")
    for r in rows:
        f.write("%s,%s\n" % (r["Time"], r["xi"]))
