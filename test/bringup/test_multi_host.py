#!/usr/bin/python3
"""Nodes on different hosts (addresses of a network namespace standing in for machines, see multi_host.sh): each
advertises its own ROS_IP, and a service call from the client reaches a stage node that itself calls the part server
on a third address."""
import os
import socket
import unittest
from urllib.parse import urlparse

import rosgraph
import rosservice
import rospy
import rostest

from art2part.srv import LoadPart, LoadPartRequest, PlanSetups, PlanSetupsRequest

EXAMPLE = os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..', 'examples',
                       'nist_ctc_01_asme1_rd.stp')
CLIENT_IP, PART_SERVER_IP, SETUP_PLANNER_IP = '10.77.0.3', '10.77.0.2', '10.77.0.4'


def host_of(uri):
    return urlparse(uri).hostname


class MultiHost(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('multi_host_client')
        rospy.wait_for_service('load_part', 60)
        rospy.wait_for_service('plan_setups', 60)

    def test_each_node_advertises_its_own_host(self):
        master = rosgraph.Master('/multi_host_client')
        self.assertEqual(host_of(rospy.get_node_uri()), CLIENT_IP)
        self.assertEqual(host_of(master.lookupNode('/part_server')), PART_SERVER_IP)
        self.assertEqual(host_of(master.lookupNode('/setup_planner')), SETUP_PLANNER_IP)
        self.assertEqual(host_of(rosservice.get_service_uri('/load_part')), PART_SERVER_IP)
        self.assertEqual(host_of(rosservice.get_service_uri('/plan_setups')), SETUP_PLANNER_IP)
        self.assertNotEqual(host_of(master.getUri()), CLIENT_IP, 'the master must be elsewhere for this to prove much')

    def test_a_stage_call_crosses_three_hosts(self):
        load = rospy.ServiceProxy('load_part', LoadPart)(LoadPartRequest(path=EXAMPLE, part_id='ctc1'))
        self.assertTrue(load.success, load.message)
        self.assertGreater(load.summary.triangles, 0)
        # setup_planner (10.77.0.4) fetches the part from part_server (10.77.0.2) to answer the client (10.77.0.3).
        plan = rospy.ServiceProxy('plan_setups', PlanSetups)(PlanSetupsRequest(part_id='ctc1', mode='3axis', level=2))
        self.assertTrue(plan.success, plan.message)
        self.assertGreater(len(plan.setups), 0)

    def test_a_connection_to_the_advertised_address_reaches_the_node(self):
        uri = urlparse(rosservice.get_service_uri('/load_part'))
        with socket.create_connection((uri.hostname, uri.port), timeout=5) as s:
            self.assertEqual(s.getpeername()[0], PART_SERVER_IP)


if __name__ == '__main__':
    rostest.rosrun('art2part', 'multi_host', MultiHost)
