"""Root conftest: registers the shared fixture modules so every test file can use them."""

pytest_plugins = ["tests.fixtures_sim", "tests.fixtures_ssh", "tests.fixtures_ui"]
