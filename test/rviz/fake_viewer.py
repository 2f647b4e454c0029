#!/usr/bin/python3
"""Stands in for rviz in the framing test: appends the view of the config it is started on (-d CONFIG) to LOG as one
JSON line, then waits to be stopped. Usage: fake_viewer.py LOG [rviz arguments...] -d CONFIG"""
import json
import signal
import sys

import yaml

log, args = sys.argv[1], sys.argv[2:]
with open(args[args.index('-d') + 1]) as f:
    view = yaml.safe_load(f)['Visualization Manager']['Views']['Current']
with open(log, 'a') as f:
    f.write(json.dumps({'focal_point': view['Focal Point'], 'distance': view['Distance']}) + '\n')
signal.sigwait([signal.SIGTERM, signal.SIGINT])
