"""patternfit.studio"""
