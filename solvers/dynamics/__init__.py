"""Dynamics models: CasADi-symbolic equations of motion, closed-form STMs, ephemerides."""
