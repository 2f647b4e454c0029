#!/usr/bin/python3
"""rviz for the cell, framed on the part: reads rviz/cell.rviz, aims its orbit camera at the part's box (from
`art2part info PART --json`) from a distance that fits the box in view, writes the result beside the ROS logs and runs
rviz on it. Without a part (or if it cannot be read) the template's view is kept.

It then follows the part server: each part it announces on `part` (art2part/LoadedPart, latched) whose box differs
from the one in view re-frames the view: the config is written again and rviz restarted on it (rviz 1 takes its view
from the config only). It ends when rviz ends (its exit status) or when ROS shuts down (rviz is stopped).

  cell_rviz.py --part FILE [--config TEMPLATE.rviz] [--write-only OUT.rviz] [--viewer rviz] [rviz arguments...]
"""
import argparse
import json
import math
import os
import subprocess
import sys
import threading

import yaml

MM_PER_M = 1000.0
# Vertical field of view of rviz's orbit camera (rad) and the margin around the part's box in the picture.
RVIZ_FOV = math.pi / 4
FRAMING_MARGIN = 1.3
# A part whose box centre or diagonal differs by more than this share of its diagonal from the one in view re-frames it.
REFRAME_SHARE = 0.01


def package_file(*parts):
    import rospkg
    return os.path.join(rospkg.RosPack().get_path('art2part'), *parts)


def art2part_cli():
    import roslib.packages
    found = roslib.packages.find_node('art2part', 'art2part')
    if not found:
        raise RuntimeError('the art2part command line is not built')
    return found[0]


def box_framing(lo, hi):
    """(centre, diagonal) of a box given by its corners (metres)."""
    return [(a + b) / 2 for a, b in zip(lo, hi)], math.dist(lo, hi)


def part_box_m(part_file):
    """(centre, diagonal) of the part's bounding box in metres, in the part frame."""
    out = subprocess.run([art2part_cli(), 'info', part_file, '--json'], check=True, capture_output=True, text=True)
    box = json.loads(out.stdout)['bounding_box']
    return box_framing([v / MM_PER_M for v in box['min']], [v / MM_PER_M for v in box['max']])


def loaded_part_box_m(msg):
    """(centre, diagonal) of a LoadedPart's box (its summary is in metres, part frame); None for an empty box."""
    lo, hi = msg.summary.box_min, msg.summary.box_max
    lo, hi = [lo.x, lo.y, lo.z], [hi.x, hi.y, hi.z]
    if any(not math.isfinite(v) for v in lo + hi) or any(a > b for a, b in zip(lo, hi)):
        return None
    return box_framing(lo, hi)


def same_framing(a, b):
    """True when two (centre, diagonal) framings give the same view: centre and diagonal agree within REFRAME_SHARE of
    the diagonal (the CLI's box and the part server's differ by rounding and tessellation)."""
    if a is None or b is None:
        return False
    tolerance = REFRAME_SHARE * max(a[1], b[1])
    return abs(a[1] - b[1]) <= tolerance and math.dist(a[0], b[0]) <= tolerance


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


def write_config(config, path):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, 'w') as f:
        yaml.safe_dump(config, f, default_flow_style=False, sort_keys=False)


class FramedViewer:
    """rviz on the framed config, restarted on a config framed anew when the part server announces a part whose box
    differs from the one in view."""

    def __init__(self, template, path, framing, command):
        self.template, self.path, self.framing, self.command = template, path, framing, command
        self.lock = threading.Lock()
        self.restarting = False
        self.process = None

    def start(self):
        config = framed_view(copy_of(self.template), *self.framing) if self.framing else copy_of(self.template)
        write_config(config, self.path)
        self.process = subprocess.Popen(self.command + ['-d', self.path])

    def stop(self):
        if self.process and self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()

    def on_part(self, msg):
        framing = loaded_part_box_m(msg)
        with self.lock:
            if framing is None or same_framing(framing, self.framing):
                return
            self.restarting = True
            self.stop()
            self.framing = framing
            self.start()
            self.restarting = False
        print('cell_rviz: view framed on part %s' % msg.id, file=sys.stderr)

    def ended(self):
        """rviz's exit status once it ended by itself (not restarted); None while it runs."""
        with self.lock:
            return None if self.restarting else self.process.poll()


def copy_of(config):
    return yaml.safe_load(yaml.safe_dump(config))


def follow_parts(viewer, rviz_args):
    """Runs `viewer` until rviz ends or ROS shuts down, re-framing it on each part announced on `part`."""
    import rospy
    from art2part.msg import LoadedPart
    # rviz is the node roslaunch named (it gets rviz_args, __name included); this process is a node of its own.
    own_args = [a for a in rviz_args if not a.startswith(('__name:=', '__log:='))]
    rospy.init_node('cell_rviz_framing', argv=[sys.argv[0]] + own_args)  # SIGINT, SIGTERM: shutdown
    viewer.start()
    rospy.Subscriber('part', LoadedPart, viewer.on_part, queue_size=1)
    try:
        while not rospy.is_shutdown():
            status = viewer.ended()
            if status is not None:
                return status
            rospy.sleep(0.2)
    except (rospy.ROSInterruptException, KeyboardInterrupt):
        pass
    finally:
        viewer.stop()
    return 0


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--part', default='', help='the part the view is framed on')
    parser.add_argument('--config', default='', help='rviz config to start from (default rviz/cell.rviz)')
    parser.add_argument('--write-only', default='', help='write the framed config here and exit')
    parser.add_argument('--viewer', default='rviz', help='the program run on the config (-d CONFIG is appended)')
    args, rviz_args = parser.parse_known_args(argv)
    with open(args.config or package_file('rviz', 'cell.rviz')) as f:
        template = yaml.safe_load(f)
    framing = None
    if args.part:
        try:
            framing = part_box_m(args.part)
        except (RuntimeError, OSError, subprocess.CalledProcessError, KeyError, ValueError) as e:
            print('cell_rviz: cannot frame the view on %s (%s); keeping the default view' % (args.part, e),
                  file=sys.stderr)
    if args.write_only:
        write_config(framed_view(template, *framing) if framing else template, args.write_only)
        return 0
    out = os.path.join(os.environ.get('ROS_HOME', os.path.expanduser('~/.ros')), 'art2part_cell.rviz')
    viewer = FramedViewer(template, out, framing, args.viewer.split() + rviz_args)
    return follow_parts(viewer, rviz_args)


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
