"""The runtime of the generated robot-side clients: what is the same in every writer and
reader node's HTTP module, whatever the product (docs/services.md, "Robot-side writers
and readers").

spl imports it as ``spl.generators.clients.runtime`` (type-checked, linted and tested
with spl); the clients generator copies its modules byte for byte into every generated
ROS 1 and ROS 2 client package as the subpackage ``<package>.runtime``, as the service
runtime is copied into services. So it imports nothing of spl and nothing outside
Python's standard library (a robot installs no more), and its modules import each other
relatively. What a product decides (the store's name, the variables of its token and
certificate authority, the collection and the fields of the node's data type) stays in
the generated ``store_client.py``, which passes it as a ``StoreAccess``.
"""
