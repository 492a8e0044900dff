<?xml version='1.0' encoding='UTF-8'?>
<indoorCore:MultiLayeredGraph xmlns:gml="http://www.opengis.net/gml/3.2" xmlns:indoorCore="http://www.opengis.net/indoorgml/1.0/core" xmlns:indoorNavi="http://www.opengis.net/indoorgml/1.0/navigation" xmlns:xlink="http://www.w3.org/1999/xlink" gml:id="CLINIC">
  <gml:metaDataProperty>
    <gml:GenericMetaData>
      <indoorNavi:translation>250000.0 120000.0</indoorNavi:translation>
      <indoorNavi:rotation>30.0</indoorNavi:rotation>
    </gml:GenericMetaData>
  </gml:metaDataProperty>
  <indoorCore:spaceLayers gml:id="SLs">
    <indoorCore:spaceLayerMember>
      <indoorCore:SpaceLayer gml:id="L1">
        <indoorCore:usage>Geometry</indoorCore:usage>
        <indoorCore:class>TOPOGRAPHIC</indoorCore:class>
        <indoorCore:nodes gml:id="N_L1">
          <indoorCore:stateMember>
            <indoorCore:State gml:id="S_COR">
              <gml:name>Corridor</gml:name>
              <indoorCore:duality>
                <indoorNavi:NavigableSpace gml:id="COR">
                  <gml:name>Corridor</gml:name>
                  <indoorCore:Geometry2D>
                    <gml:Polygon gml:id="G_COR">
                      <gml:exterior>
                        <gml:LinearRing>
                          <gml:posList>0.0 610.0 3000.0 610.0 3000.0 890.0 0.0 890.0 0.0 610.0</gml:posList>
                        </gml:LinearRing>
                      </gml:exterior>
                    </gml:Polygon>
                  </indoorCore:Geometry2D>
                </indoorNavi:NavigableSpace>
              </indoorCore:duality>
              <indoorCore:geometry>
                <gml:Point gml:id="P_COR" srsDimension="2">
                  <gml:pos>1500.0 750.0</gml:pos>
                </gml:Point>
              </indoorCore:geometry>
            </indoorCore:State>
          </indoorCore:stateMember>
          <indoorCore:stateMember>
            <indoorCore:State gml:id="S_R1">
              <gml:name>Waiting room</gml:name>
              <indoorCore:duality>
                <indoorNavi:NavigableSpace gml:id="R1">
                  <gml:name>Waiting room</gml:name>
                  <indoorCore:Geometry2D>
                    <gml:Polygon gml:id="G_R1">
                      <gml:exterior>
                        <gml:LinearRing>
                          <gml:posList>0.0 0.0 1000.0 0.0 1000.0 590.0 0.0 590.0 0.0 0.0</gml:posList>
                        </gml:LinearRing>
                      </gml:exterior>
                    </gml:Polygon>
                  </indoorCore:Geometry2D>
                </indoorNavi:NavigableSpace>
              </indoorCore:duality>
              <indoorCore:geometry>
                <gml:Point gml:id="P_R1" srsDimension="2">
                  <gml:pos>500.0 295.0</gml:pos>
                </gml:Point>
              </indoorCore:geometry>
            </indoorCore:State>
          </indoorCore:stateMember>
          <indoorCore:stateMember>
            <indoorCore:State gml:id="S_D1">
              <gml:name>Door Waiting room</gml:name>
              <indoorCore:duality>
                <indoorNavi:ConnectionSpace gml:id="D1">
                  <gml:name>Door Waiting room</gml:name>
                  <indoorCore:Geometry2D>
                    <gml:Polygon gml:id="G_D1">
                      <gml:exterior>
                        <gml:LinearRing>
                          <gml:posList>450.0 590.0 540.0 590.0 540.0 610.0 450.0 610.0 450.0 590.0</gml:posList>
                        </gml:LinearRing>
                      </gml:exterior>
                    </gml:Polygon>
                  </indoorCore:Geometry2D>
                </indoorNavi:ConnectionSpace>
              </indoorCore:duality>
              <indoorCore:geometry>
                <gml:Point gml:id="P_D1" srsDimension="2">
                  <gml:pos>495.0 600.0</gml:pos>
                </gml:Point>
              </indoorCore:geometry>
            </indoorCore:State>
          </indoorCore:stateMember>
          <indoorCore:stateMember>
            <indoorCore:State gml:id="S_R2">
              <gml:name>Exam room 1</gml:name>
              <indoorCore:duality>
                <indoorNavi:NavigableSpace gml:id="R2">
                  <gml:name>Exam room 1</gml:name>
                  <indoorCore:Geometry2D>
                    <gml:Polygon gml:id="G_R2">
                      <gml:exterior>
                        <gml:LinearRing>
                          <gml:posList>1000.0 0.0 2000.0 0.0 2000.0 590.0 1000.0 590.0 1000.0 0.0</gml:posList>
                        </gml:LinearRing>
                      </gml:exterior>
                    </gml:Polygon>
                  </indoorCore:Geometry2D>
                </indoorNavi:NavigableSpace>
              </indoorCore:duality>
              <indoorCore:geometry>
                <gml:Point gml:id="P_R2" srsDimension="2">
                  <gml:pos>1500.0 295.0</gml:pos>
                </gml:Point>
              </indoorCore:geometry>
            </indoorCore:State>
          </indoorCore:stateMember>
          <indoorCore:stateMember>
            <indoorCore:State gml:id="S_D2">
              <gml:name>Door Exam room 1</gml:name>
              <indoorCore:duality>
                <indoorNavi:ConnectionSpace gml:id="D2">
                  <gml:name>Door Exam room 1</gml:name>
                  <indoorCore:Geometry2D>
                    <gml:Polygon gml:id="G_D2">
                      <gml:exterior>
                        <gml:LinearRing>
                          <gml:posList>1450.0 590.0 1540.0 590.0 1540.0 610.0 1450.0 610.0 1450.0 590.0</gml:posList>
                        </gml:LinearRing>
                      </gml:exterior>
                    </gml:Polygon>
                  </indoorCore:Geometry2D>
                </indoorNavi:ConnectionSpace>
              </indoorCore:duality>
              <indoorCore:geometry>
                <gml:Point gml:id="P_D2" srsDimension="2">
                  <gml:pos>1495.0 600.0</gml:pos>
                </gml:Point>
              </indoorCore:geometry>
            </indoorCore:State>
          </indoorCore:stateMember>
          <indoorCore:stateMember>
            <indoorCore:State gml:id="S_R3">
              <gml:name>Exam room 2</gml:name>
              <indoorCore:duality>
                <indoorNavi:NavigableSpace gml:id="R3">
                  <gml:name>Exam room 2</gml:name>
                  <indoorCore:Geometry2D>
                    <gml:Polygon gml:id="G_R3">
                      <gml:exterior>
                        <gml:LinearRing>
                          <gml:posList>2000.0 0.0 3000.0 0.0 3000.0 590.0 2000.0 590.0 2000.0 0.0</gml:posList>
                        </gml:LinearRing>
                      </gml:exterior>
                    </gml:Polygon>
                  </indoorCore:Geometry2D>
                </indoorNavi:NavigableSpace>
              </indoorCore:duality>
              <indoorCore:geometry>
                <gml:Point gml:id="P_R3" srsDimension="2">
                  <gml:pos>2500.0 295.0</gml:pos>
                </gml:Point>
              </indoorCore:geometry>
            </indoorCore:State>
          </indoorCore:stateMember>
          <indoorCore:stateMember>
            <indoorCore:State gml:id="S_D3">
              <gml:name>Door Exam room 2</gml:name>
              <indoorCore:duality>
                <indoorNavi:ConnectionSpace gml:id="D3">
                  <gml:name>Door Exam room 2</gml:name>
                  <indoorCore:Geometry2D>
                    <gml:Polygon gml:id="G_D3">
                      <gml:exterior>
                        <gml:LinearRing>
                          <gml:posList>2450.0 590.0 2540.0 590.0 2540.0 610.0 2450.0 610.0 2450.0 590.0</gml:posList>
                        </gml:LinearRing>
                      </gml:exterior>
                    </gml:Polygon>
                  </indoorCore:Geometry2D>
                </indoorNavi:ConnectionSpace>
              </indoorCore:duality>
              <indoorCore:geometry>
                <gml:Point gml:id="P_D3" srsDimension="2">
                  <gml:pos>2495.0 600.0</gml:pos>
                </gml:Point>
              </indoorCore:geometry>
            </indoorCore:State>
          </indoorCore:stateMember>
          <indoorCore:stateMember>
            <indoorCore:State gml:id="S_R4">
              <gml:name>Office</gml:name>
              <indoorCore:duality>
                <indoorNavi:NavigableSpace gml:id="R4">
                  <gml:name>Office</gml:name>
                  <indoorCore:Geometry2D>
                    <gml:Polygon gml:id="G_R4">
                      <gml:exterior>
                        <gml:LinearRing>
                          <gml:posList>0.0 910.0 1200.0 910.0 1200.0 1500.0 0.0 1500.0 0.0 910.0</gml:posList>
                        </gml:LinearRing>
                      </gml:exterior>
                    </gml:Polygon>
                  </indoorCore:Geometry2D>
                </indoorNavi:NavigableSpace>
              </indoorCore:duality>
              <indoorCore:geometry>
                <gml:Point gml:id="P_R4" srsDimension="2">
                  <gml:pos>600.0 1205.0</gml:pos>
                </gml:Point>
              </indoorCore:geometry>
            </indoorCore:State>
          </indoorCore:stateMember>
          <indoorCore:stateMember>
            <indoorCore:State gml:id="S_D4">
              <gml:name>Door Office</gml:name>
              <indoorCore:duality>
                <indoorNavi:ConnectionSpace gml:id="D4">
                  <gml:name>Door Office</gml:name>
                  <indoorCore:Geometry2D>
                    <gml:Polygon gml:id="G_D4">
                      <gml:exterior>
                        <gml:LinearRing>
                          <gml:posList>550.0 890.0 640.0 890.0 640.0 910.0 550.0 910.0 550.0 890.0</gml:posList>
                        </gml:LinearRing>
                      </gml:exterior>
                    </gml:Polygon>
                  </indoorCore:Geometry2D>
                </indoorNavi:ConnectionSpace>
              </indoorCore:duality>
              <indoorCore:geometry>
                <gml:Point gml:id="P_D4" srsDimension="2">
                  <gml:pos>595.0 900.0</gml:pos>
                </gml:Point>
              </indoorCore:geometry>
            </indoorCore:State>
          </indoorCore:stateMember>
          <indoorCore:stateMember>
            <indoorCore:State gml:id="S_R5">
              <gml:name>Treatment room</gml:name>
              <indoorCore:duality>
                <indoorNavi:NavigableSpace gml:id="R5">
                  <gml:name>Treatment room</gml:name>
                  <indoorCore:Geometry2D>
                    <gml:Polygon gml:id="G_R5">
                      <gml:exterior>
                        <gml:LinearRing>
                          <gml:posList>1200.0 910.0 2000.0 910.0 2000.0 1500.0 1200.0 1500.0 1200.0 910.0</gml:posList>
                        </gml:LinearRing>
                      </gml:exterior>
                    </gml:Polygon>
                  </indoorCore:Geometry2D>
                </indoorNavi:NavigableSpace>
              </indoorCore:duality>
              <indoorCore:geometry>
                <gml:Point gml:id="P_R5" srsDimension="2">
                  <gml:pos>1600.0 1205.0</gml:pos>
                </gml:Point>
              </indoorCore:geometry>
            </indoorCore:State>
          </indoorCore:stateMember>
          <indoorCore:stateMember>
            <indoorCore:State gml:id="S_D5">
              <gml:name>Door Treatment room</gml:name>
              <indoorCore:duality>
                <indoorNavi:ConnectionSpace gml:id="D5">
                  <gml:name>Door Treatment room</gml:name>
                  <indoorCore:Geometry2D>
                    <gml:Polygon gml:id="G_D5">
                      <gml:exterior>
                        <gml:LinearRing>
                          <gml:posList>1550.0 890.0 1640.0 890.0 1640.0 910.0 1550.0 910.0 1550.0 890.0</gml:posList>
                        </gml:LinearRing>
                      </gml:exterior>
                    </gml:Polygon>
                  </indoorCore:Geometry2D>
                </indoorNavi:ConnectionSpace>
              </indoorCore:duality>
              <indoorCore:geometry>
                <gml:Point gml:id="P_D5" srsDimension="2">
                  <gml:pos>1595.0 900.0</gml:pos>
                </gml:Point>
              </indoorCore:geometry>
            </indoorCore:State>
          </indoorCore:stateMember>
          <indoorCore:stateMember>
            <indoorCore:State gml:id="S_R6">
              <gml:name>Storage</gml:name>
              <indoorCore:duality>
                <indoorNavi:NavigableSpace gml:id="R6">
                  <gml:name>Storage</gml:name>
                  <indoorCore:Geometry2D>
                    <gml:Polygon gml:id="G_R6">
                      <gml:exterior>
                        <gml:LinearRing>
                          <gml:posList>2000.0 910.0 3000.0 910.0 3000.0 1500.0 2000.0 1500.0 2000.0 910.0</gml:posList>
                        </gml:LinearRing>
                      </gml:exterior>
                    </gml:Polygon>
                  </indoorCore:Geometry2D>
                </indoorNavi:NavigableSpace>
              </indoorCore:duality>
              <indoorCore:geometry>
                <gml:Point gml:id="P_R6" srsDimension="2">
                  <gml:pos>2500.0 1205.0</gml:pos>
                </gml:Point>
              </indoorCore:geometry>
            </indoorCore:State>
          </indoorCore:stateMember>
          <indoorCore:stateMember>
            <indoorCore:State gml:id="S_D6">
              <gml:name>Door Storage</gml:name>
              <indoorCore:duality>
                <indoorNavi:ConnectionSpace gml:id="D6">
                  <gml:name>Door Storage</gml:name>
                  <indoorCore:Geometry2D>
                    <gml:Polygon gml:id="G_D6">
                      <gml:exterior>
                        <gml:LinearRing>
                          <gml:posList>2450.0 890.0 2540.0 890.0 2540.0 910.0 2450.0 910.0 2450.0 890.0</gml:posList>
                        </gml:LinearRing>
                      </gml:exterior>
                    </gml:Polygon>
                  </indoorCore:Geometry2D>
                </indoorNavi:ConnectionSpace>
              </indoorCore:duality>
              <indoorCore:geometry>
                <gml:Point gml:id="P_D6" srsDimension="2">
                  <gml:pos>2495.0 900.0</gml:pos>
                </gml:Point>
              </indoorCore:geometry>
            </indoorCore:State>
          </indoorCore:stateMember>
          <indoorCore:stateMember>
            <indoorCore:State gml:id="S_DESK">
              <gml:name>Reception desk</gml:name>
              <indoorCore:duality>
                <indoorNavi:NonNavigableSpace gml:id="DESK">
                  <gml:name>Reception desk</gml:name>
                  <indoorCore:Geometry2D>
                    <gml:Polygon gml:id="G_DESK">
                      <gml:exterior>
                        <gml:LinearRing>
                          <gml:posList>300.0 350.0 700.0 350.0 700.0 450.0 300.0 450.0 300.0 350.0</gml:posList>
                        </gml:LinearRing>
                      </gml:exterior>
                    </gml:Polygon>
                  </indoorCore:Geometry2D>
                </indoorNavi:NonNavigableSpace>
              </indoorCore:duality>
              <indoorCore:geometry>
                <gml:Point gml:id="P_DESK" srsDimension="2">
                  <gml:pos>500.0 400.0</gml:pos>
                </gml:Point>
              </indoorCore:geometry>
            </indoorCore:State>
          </indoorCore:stateMember>
          <indoorCore:stateMember>
            <indoorCore:State gml:id="S_PIL">
              <gml:name>Pillar</gml:name>
              <indoorCore:duality>
                <indoorNavi:NonNavigableSpace gml:id="PIL">
                  <gml:name>Pillar</gml:name>
                  <indoorCore:Geometry2D>
                    <gml:Polygon gml:id="G_PIL">
                      <gml:exterior>
                        <gml:LinearRing>
                          <gml:posList>200.0 1200.0 260.0 1200.0 260.0 1260.0 200.0 1260.0 200.0 1200.0</gml:posList>
                        </gml:LinearRing>
                      </gml:exterior>
                    </gml:Polygon>
                  </indoorCore:Geometry2D>
                </indoorNavi:NonNavigableSpace>
              </indoorCore:duality>
              <indoorCore:geometry>
                <gml:Point gml:id="P_PIL" srsDimension="2">
                  <gml:pos>230.0 1230.0</gml:pos>
                </gml:Point>
              </indoorCore:geometry>
            </indoorCore:State>
          </indoorCore:stateMember>
        </indoorCore:nodes>
        <indoorCore:edges gml:id="E_L1">
          <indoorCore:transitionMember>
            <indoorCore:Transition gml:id="T_R1_D1">
              <indoorCore:weight>1.0</indoorCore:weight>
              <indoorCore:connects xlink:href="#S_R1"/>
              <indoorCore:connects xlink:href="#S_D1"/>
            </indoorCore:Transition>
          </indoorCore:transitionMember>
          <indoorCore:transitionMember>
            <indoorCore:Transition gml:id="T_D1_COR">
              <indoorCore:weight>1.0</indoorCore:weight>
              <indoorCore:connects xlink:href="#S_D1"/>
              <indoorCore:connects xlink:href="#S_COR"/>
            </indoorCore:Transition>
          </indoorCore:transitionMember>
          <indoorCore:transitionMember>
            <indoorCore:Transition gml:id="T_R2_D2">
              <indoorCore:weight>1.0</indoorCore:weight>
              <indoorCore:connects xlink:href="#S_R2"/>
              <indoorCore:connects xlink:href="#S_D2"/>
            </indoorCore:Transition>
          </indoorCore:transitionMember>
          <indoorCore:transitionMember>
            <indoorCore:Transition gml:id="T_D2_COR">
              <indoorCore:weight>1.0</indoorCore:weight>
              <indoorCore:connects xlink:href="#S_D2"/>
              <indoorCore:connects xlink:href="#S_COR"/>
            </indoorCore:Transition>
          </indoorCore:transitionMember>
          <indoorCore:transitionMember>
            <indoorCore:Transition gml:id="T_R3_D3">
              <indoorCore:weight>1.0</indoorCore:weight>
              <indoorCore:connects xlink:href="#S_R3"/>
              <indoorCore:connects xlink:href="#S_D3"/>
            </indoorCore:Transition>
          </indoorCore:transitionMember>
          <indoorCore:transitionMember>
            <indoorCore:Transition gml:id="T_D3_COR">
              <indoorCore:weight>1.0</indoorCore:weight>
              <indoorCore:connects xlink:href="#S_D3"/>
              <indoorCore:connects xlink:href="#S_COR"/>
            </indoorCore:Transition>
          </indoorCore:transitionMember>
          <indoorCore:transitionMember>
            <indoorCore:Transition gml:id="T_R4_D4">
              <indoorCore:weight>1.0</indoorCore:weight>
              <indoorCore:connects xlink:href="#S_R4"/>
              <indoorCore:connects xlink:href="#S_D4"/>
            </indoorCore:Transition>
          </indoorCore:transitionMember>
          <indoorCore:transitionMember>
            <indoorCore:Transition gml:id="T_D4_COR">
              <indoorCore:weight>1.0</indoorCore:weight>
              <indoorCore:connects xlink:href="#S_D4"/>
              <indoorCore:connects xlink:href="#S_COR"/>
            </indoorCore:Transition>
          </indoorCore:transitionMember>
          <indoorCore:transitionMember>
            <indoorCore:Transition gml:id="T_R5_D5">
              <indoorCore:weight>1.0</indoorCore:weight>
              <indoorCore:connects xlink:href="#S_R5"/>
              <indoorCore:connects xlink:href="#S_D5"/>
            </indoorCore:Transition>
          </indoorCore:transitionMember>
          <indoorCore:transitionMember>
            <indoorCore:Transition gml:id="T_D5_COR">
              <indoorCore:weight>1.0</indoorCore:weight>
              <indoorCore:connects xlink:href="#S_D5"/>
              <indoorCore:connects xlink:href="#S_COR"/>
            </indoorCore:Transition>
          </indoorCore:transitionMember>
          <indoorCore:transitionMember>
            <indoorCore:Transition gml:id="T_R6_D6">
              <indoorCore:weight>1.0</indoorCore:weight>
              <indoorCore:connects xlink:href="#S_R6"/>
              <indoorCore:connects xlink:href="#S_D6"/>
            </indoorCore:Transition>
          </indoorCore:transitionMember>
          <indoorCore:transitionMember>
            <indoorCore:Transition gml:id="T_D6_COR">
              <indoorCore:weight>1.0</indoorCore:weight>
              <indoorCore:connects xlink:href="#S_D6"/>
              <indoorCore:connects xlink:href="#S_COR"/>
            </indoorCore:Transition>
          </indoorCore:transitionMember>
        </indoorCore:edges>
      </indoorCore:SpaceLayer>
    </indoorCore:spaceLayerMember>
    <indoorCore:spaceLayerMember>
      <indoorCore:SpaceLayer gml:id="L2">
        <indoorCore:usage>Navigation</indoorCore:usage>
        <indoorCore:class>TOPOGRAPHIC</indoorCore:class>
        <indoorCore:nodes gml:id="N_L2">
          <indoorCore:stateMember>
            <indoorCore:State gml:id="NAV_ENTRANCE">
              <gml:name>Entrance</gml:name>
              <indoorCore:duality xlink:href="#COR"/>
            </indoorCore:State>
          </indoorCore:stateMember>
        </indoorCore:nodes>
        <indoorCore:edges gml:id="E_L2"/>
      </indoorCore:SpaceLayer>
    </indoorCore:spaceLayerMember>
  </indoorCore:spaceLayers>
</indoorCore:MultiLayeredGraph>
