"""The quick configuration's full run, built once per test session and shared by the workflow tests."""

import pytest

from tests.helpers import copy_workflow, snakemake


@pytest.fixture(scope="session")
def quick_run(tmp_path_factory):
    """A copy of the workflow in which the quick configuration's whole DAG has run (minutes: built once).

    Tests restore what they edit in it, and changed configs are override files of their own.
    """
    work = copy_workflow(tmp_path_factory.mktemp("workflow"))
    snakemake(work)
    return work
