"""`aocs gains`' outputs from the designs of aocs_design: the firmware's C gain tables and their
registration (tables), and the design report docs/gains/ (report)."""
