"""Pose regression (Sections 2 and 3): features -> pose.

``pose_space`` is the pose PCA of Eq. 1 (90 % of the variance), ``pose_encoding`` the heading code,
``kernels`` the Gaussian kernel of Eq. 3, ``mvrvm`` the multivariate RVM of Eq. 2 (its shared-precision step
in ``mvrvm_alpha``, its posterior in ``mvrvm_posterior``), ``baselines`` the comparison regressors, ``stored`` a
trained regressor as arrays.
"""
