"""The ``features`` config keys each feature fit reads (``FeatureModel.fit_rows``), without importing the fits:
the workflow passes a fit only its method's keys (``workflow_config.feature_params``) and ``fit-features``
requires only those."""

FIT_KEYS = {
    "mppca": ("n_components", "n_latent", "max_iter", "tol", "fit_subsample", "heading_sense"),
    "kmeans": ("n_components", "max_iter", "fit_subsample", "kmeans_neighbours", "heading_sense"),
}
