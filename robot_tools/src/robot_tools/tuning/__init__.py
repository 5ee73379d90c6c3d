"""Tuning: an Optuna study over a robot's tune space, its objective and the held-out verdict."""
