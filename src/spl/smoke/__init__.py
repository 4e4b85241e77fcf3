"""Live rehearsal of a deployment bundle's ROS graph with the real ROS 1 (``spl smoke``).

Neither parsing, resolution nor generation: this package takes a written bundle, starts
its containers' ROS graphs with Debian's ROS 1 (roscore, roslaunch, rospy for the system
Python) and compares what runs with the resolved model the bundle carries.

- :mod:`spl.smoke.plan`: what the bundle's model says the live graph must be;
- :mod:`spl.smoke.processes`: finding ROS, starting and always ending processes;
- :mod:`spl.smoke.standin`: the stand-in nodes and endpoint relays (a script run by
  the Python that has rospy, never imported here);
- :mod:`spl.smoke.live`: reading the masters and comparing, row by row;
- :mod:`spl.smoke.rehearsal`: the run itself; :mod:`spl.smoke.report`: its output.

Nothing here is imported by the pipeline; only the ``smoke`` and ``validate --smoke``
commands load it.
"""
