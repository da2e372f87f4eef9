"""Input and output shared by every stage: atomic writes, voxpose's HDF5 layouts and BVH files.

``atomic`` (every output complete or absent), ``hdf5`` (layout name and version, metadata, generic layouts),
``bvh`` (reading and writing the motion-capture files of Section 6).
"""
