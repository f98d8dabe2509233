"""patternfit.sim"""
