"""A trained model applied to new recordings: the model file, prediction and its outputs.

``model_file`` bundles everything ``voxpose predict`` needs; ``predict`` carves, describes and regresses
every frame as the workflow does (Sections 3-5); ``outputs`` writes BVH, CSV and HDF5; ``animation``
renders voxels with the estimated skeleton.
"""
