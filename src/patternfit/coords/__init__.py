"""patternfit.coords"""
