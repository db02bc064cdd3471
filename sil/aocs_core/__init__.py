"""aocs_core: the facts every other package shares and nothing else.

- conventions: quaternions (scalar last, Shuster product), A(q), CRP / MRP /
  Euler 3-2-1, pointing error, arcsec per radian (SPEC 1), the one Python
  copy of the firmware's conventions, pinned against the C code by tests;
- paths: where the repository, the build tree, the binaries and the
  generated LCM bindings are, and the firmware facts read from the build.

It imports no other aocs package.
"""
