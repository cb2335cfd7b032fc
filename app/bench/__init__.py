"""`shadelab bench <technique>`: each technique module offers technique(quick) -> Technique."""
from app.bench import lighting2d, paint, snowflake, volume

TECHNIQUES = {"snowflake": snowflake.technique, "paint": paint.technique, "volume": volume.technique,
              "lighting2d": lighting2d.technique}
