"""The runtime of the generated data-acquisition services: what is the same in every
service, whatever the product (docs/services.md, "The runtime package").

spl imports it as ``spl.generators.service.runtime`` (type-checked, linted and tested
with spl); the service generator copies its modules byte for byte into every generated
service as the subpackage ``<package>.runtime``. So it imports nothing of spl, only the
libraries every service depends on (requirements.txt), and its modules import each other
relatively. What a product decides (names, data model, settings' variables) stays in the
generated modules, which pass it to the runtime as arguments.
"""
