"""The ``voxpose`` command: the workflow's rules call it, users run it on their own data.

``main`` builds the parser and turns a ``VoxposeError`` into one line and exit status 2; ``pipeline``,
``claims`` and ``model`` define the subcommands.
"""
