<?xml version="1.0" encoding="UTF-8"?>
<tileset version="1.10" tiledversion="1.10.2" name="t" tilewidth="16" tileheight="16" tilecount="4" columns="2">
 <tileoffset x="2" y="-3"/>
 <image source="t.png" width="32" height="32"/>
 <tile id="1" type="Wall"><objectgroup draworder="index"><object id="1" x="2" y="2" width="8" height="4" rotation="15"/><object id="2" x="0" y="8"><polygon points="0,0 16,0 8,8"/></object></objectgroup></tile>
 <tile id="2"><objectgroup><object id="1" x="4" y="4" width="8" height="8"><ellipse/></object><object id="3" x="0" y="0"><polyline points="0,0 16,16"/></object></objectgroup></tile>
 <tile id="3" x="0" y="0" width="8" height="8"><image width="16" height="16" source="u.png"/></tile>
</tileset>
