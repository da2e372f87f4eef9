"""Input and output shared by every stage: atomic writes, voxpose's HDF5 layouts and BVH files.

``atomic`` (every output complete or absent), ``hdf5`` (layout name and version, metadata, generic layouts),
``checksum`` (every HDF5 file's content checksum, written last and verified on every read), ``cache`` (the damaged
files of a results folder and the rules that make them: ``voxpose verify``), ``bvh`` (reading and writing the
motion-capture files of Section 6).
"""
