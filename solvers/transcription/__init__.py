"""Transcriptions of optimal control problems into NLPs, one method per module."""
