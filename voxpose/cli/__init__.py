"""The ``voxpose`` command: the workflow's rules call it, users run it on their own data.

``main`` builds the parser from one module per subcommand (``describe`` defines ``voxpose describe``) and
turns a ``VoxposeError`` into one line and exit status 2; ``common`` holds the argument helpers they share.
A subcommand imports the library inside ``run``, so ``voxpose --help`` stays fast.
"""
