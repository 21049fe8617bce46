"""Evaluation: the Fail/Partial/Success protocol over episodes, reports and videos."""
