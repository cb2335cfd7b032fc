"""`shadelab bench <technique>`: each technique module offers technique(quick) -> Technique. The bench
layer's mapping from a workspace's name to the technique its dock charts is WORKSPACE_TECHNIQUE."""
from app.bench import clouds, lighting2d, paint, shadows, snowflake, volume

TECHNIQUES = {"snowflake": snowflake.technique, "paint": paint.technique, "volume": volume.technique,
              "lighting2d": lighting2d.technique, "clouds": clouds.technique, "shadows": shadows.technique}
WORKSPACE_TECHNIQUE = {"lighting2d": "lighting2d", "volume": "volume", "snowflake": "snowflake", "clouds": "clouds",
                       "lights3d": "shadows"}
