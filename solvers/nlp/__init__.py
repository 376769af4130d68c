"""NLP back ends: CasADi (IPOPT, SQP) and the papers own solvers written here."""
