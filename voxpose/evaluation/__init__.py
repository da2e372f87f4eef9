"""Experiments and their artifacts (Section 6): Eq. 6 errors, Table 1, Table 2, Figure 4, the gallery.

``run`` trains and tests one experiment, ``metrics`` holds Eq. 6 and the per-joint errors, ``tables`` and
``figures`` (``claims_figures`` for the measured claims, ``gallery`` for the voxel renderings) write the
artifacts.
"""
