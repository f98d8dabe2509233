"""patternfit.cli"""
