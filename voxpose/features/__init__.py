"""Feature transformation (Section 5): a frame's set of descriptors -> one feature vector.

``mppca`` fits the Mixture of Probabilistic PCA, ``kmeans`` the baseline codebook; ``frame`` computes Eq. 5
(the mean posterior responsibilities) and the K-means soft histogram; ``model`` is the fitted
transformation as the workflow stores it; ``silhouette`` the 2D-shape-context features of the comparison.
"""
