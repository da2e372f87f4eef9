"""Motions and poses (Sections 2 and 6): BVH motion capture -> the 42 canonical joint angles of Section 2.

The pose is 3 angles for each of 14 joints (``canon``); ``joint_map`` and ``load`` bring any skeleton family
onto them (``reference_pose`` finds a leading calibration pose on any of them). Section 6's motion types:
``generate`` makes the embedded default motions (on ``generated_skeleton``, from the angle plans of ``gait``
and the ground contact of ``ground``), ``derive`` spirals, drunk walks and turned copies of real walks, and
``paths`` holds the heading curves both share. ``data`` holds a loaded motion and its file layout;
``pose_kinematics`` poses the canonical body, ``output_skeleton`` writes predictions back as BVH.
"""
