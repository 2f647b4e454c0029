#!/usr/bin/python3
"""rviz for the cell, framed on the part: reads rviz/cell.rviz, aims its orbit camera at the part's box (from
`art2part info PART --json`) from a distance that fits the box in view, writes the result beside the ROS logs and runs
rviz on it. Without a part (or if it cannot be read) the template's view is kept.

  cell_rviz.py --part FILE [--config TEMPLATE.rviz] [--write-only OUT.rviz] [rviz arguments...]
"""
import argparse
import json
import math
import os
import subprocess
import sys

import yaml

MM_PER_M = 1000.0
# Vertical field of view of rviz's orbit camera (rad) and the margin around the part's box in the picture.
RVIZ_FOV = math.pi / 4
FRAMING_MARGIN = 1.3


def package_file(*parts):
    import rospkg
    return os.path.join(rospkg.RosPack().get_path('art2part'), *parts)


def art2part_cli():
    import roslib.packages
    found = roslib.packages.find_node('art2part', 'art2part')
    if not found:
        raise RuntimeError('the art2part command line is not built')
    return found[0]


def part_box_m(part_file):
    """(centre, diagonal) of the part's bounding box in metres, in the part frame."""
    out = subprocess.run([art2part_cli(), 'info', part_file, '--json'], check=True, capture_output=True, text=True)
    box = json.loads(out.stdout)['bounding_box']
    lo = [v / MM_PER_M for v in box['min']]
    hi = [v / MM_PER_M for v in box['max']]
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    return centre, math.dist(lo, hi)


def framed_view(config, centre, diagonal):
    """Points the orbit view at `centre` from where a sphere round the box fills the view; scales the TF axes and the
    grid to the part."""
    view = config['Visualization Manager']['Views']['Current']
    view['Focal Point'] = {'X': centre[0], 'Y': centre[1], 'Z': centre[2]}
    view['Distance'] = FRAMING_MARGIN * (diagonal / 2) / math.tan(RVIZ_FOV / 2)
    view['Near Clip Distance'] = max(1e-4, diagonal / 1000)
    grid_cell = 10 ** round(math.log10(diagonal / 10))  # a power of ten, about a tenth of the part
    for display in config['Visualization Manager']['Displays']:
        if display.get('Class') == 'rviz/TF':
            display['Marker Scale'] = max(0.02, diagonal / 4)
        elif display.get('Class') == 'rviz/Grid':
            display['Cell Size'] = grid_cell
            display['Plane Cell Count'] = max(2, math.ceil(2 * diagonal / grid_cell))
            display['Name'] = 'Grid (%g m cells)' % grid_cell
    return config


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--part', default='', help='the part the view is framed on')
    parser.add_argument('--config', default='', help='rviz config to start from (default rviz/cell.rviz)')
    parser.add_argument('--write-only', default='', help='write the framed config here and exit')
    args, rviz_args = parser.parse_known_args(argv)
    with open(args.config or package_file('rviz', 'cell.rviz')) as f:
        config = yaml.safe_load(f)
    if args.part:
        try:
            centre, diagonal = part_box_m(args.part)
            config = framed_view(config, centre, diagonal)
        except (RuntimeError, OSError, subprocess.CalledProcessError, KeyError, ValueError) as e:
            print('cell_rviz: cannot frame the view on %s (%s); keeping the default view' % (args.part, e),
                  file=sys.stderr)
    out = args.write_only or os.path.join(os.environ.get('ROS_HOME', os.path.expanduser('~/.ros')),
                                          'art2part_cell.rviz')
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    with open(out, 'w') as f:
        yaml.safe_dump(config, f, default_flow_style=False, sort_keys=False)
    if args.write_only:
        return 0
    os.execvp('rviz', ['rviz', '-d', out] + rviz_args)


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
