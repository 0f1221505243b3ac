"""This type's report layout: its sections are the ones every linkage shares
(linkcli.analysis.sections) and those its solver records, laid out generically."""

from __future__ import annotations


def report_tables(name: str, section, length_unit: str, angle_unit: str) -> list:
    """No tailored tables: the generic layout of linkcli.report serves these sections."""
    return []
