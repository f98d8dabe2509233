"""patternfit.fit"""
