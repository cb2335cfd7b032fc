"""`shadelab bench <technique>`: each technique module offers technique() -> Technique."""
from app.bench import paint, snowflake

TECHNIQUES = {"snowflake": snowflake.technique, "paint": paint.technique}
