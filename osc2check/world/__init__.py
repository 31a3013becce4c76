"""The world the checker places scenarios in and the runner builds: actors and roads.

``catalogue``: what each kind of actor is (footprint, mass, limits); the road
network interface and its implementations live beside it.
"""
