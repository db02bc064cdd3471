"""`aocs compare` (every applicable law on one scenario, side by side) and
`aocs results` (docs/results.md for every reference scenario of SPEC 4)."""
