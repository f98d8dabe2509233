"""patternfit.edit"""
