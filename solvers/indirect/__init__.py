"""Indirect (Pontryagin) solutions used as independent checks of the direct transcriptions."""
