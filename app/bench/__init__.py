"""`shadelab bench <technique>`: each technique module offers technique() -> Technique."""
from app.bench import snowflake

TECHNIQUES = {"snowflake": snowflake.technique}
