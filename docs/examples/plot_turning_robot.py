"""
A robot that turns: planning in (x, y, theta)
=============================================

A 1.6 m x 0.5 m cart and a wall with a 1.0 m door: lying sideways the cart cannot pass, so a planner
for a robot that only translates finds no way. With ``headings=72`` the configuration space is a pose
grid ``[heading, row, col]`` (:func:`gridfield.geometry.cspace.apply_robot`): each heading slice holds the
C-obstacles of the cart turned anywhere inside its 5-degree bin, the heading axis wraps round, and the
default planner descends its navigation function in x, y and heading
(:func:`gridfield.following.posefollow.plan_poses`). The cart turns lengthwise, passes the door and turns
to the goal heading.
"""

import numpy as np

from gridfield.core.grid import Grid, GridMap
from gridfield.geometry.cspace import apply_robot
from gridfield.geometry.world import Robot
from gridfield.planners import plan
from gridfield.plot.poses import plot_footprints, plot_pose_space

occ = np.zeros((100, 100), bool)  # a 10 m x 10 m room at 0.1 m
occ[49:51, :] = True
occ[49:51, 45:55] = False  # the 1.0 m door
occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = True
room = GridMap(Grid((100, 100), 0.1), occ, source="room with a door")
cart = Robot(vertices=[[-0.8, -0.25], [0.8, -0.25], [0.8, 0.25], [-0.8, 0.25]])

translating = plan("wavefront-octile", apply_robot(room, cart), (5.0, 2.0), (5.0, 8.0))
print("translating only:", translating.status)

poses = apply_robot(room, cart, headings=72)
path = plan("potential", poses, (5.0, 2.0, 0.0), (5.0, 8.0, np.pi / 4))
print("turning:", path.status, f"length {path.length:.2f} m through", len(path.poses), "poses")

# plotting computes nothing: the figures draw the pose grid and the path they are given
import matplotlib.pyplot as plt  # noqa: E402

fig = plt.figure(figsize=(13, 6), layout="constrained")
plot_footprints(poses, path, ax=fig.add_subplot(1, 2, 1))
plot_pose_space(poses, path, ax=fig.add_subplot(1, 2, 2, projection="3d"))
