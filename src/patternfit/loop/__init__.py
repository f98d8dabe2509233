"""patternfit.loop"""
