"""Keep pytest away from the benchmark scripts.

The project's ``testpaths`` (``tests``, ``src/pmplan``) never reach this folder; this file makes
sure that even ``pytest benchmarks`` (with the project's ``--doctest-modules``) imports none of
the scripts, which are slow, print, and write files.
"""

collect_ignore_glob = ["*.py"]
