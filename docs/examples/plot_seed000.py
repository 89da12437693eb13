"""
Seed 000: the stall point and the escapes
=========================================

placeholder
"""
import matplotlib.pyplot as plt

fig, ax = plt.subplots()
ax.plot([0, 1])
