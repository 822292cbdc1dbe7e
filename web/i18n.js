// geoslice web client: English and Simplified Chinese. The first of navigator.languages
// (the browser's Accept-Language) that is Chinese picks zh; a saved choice or the
// permalink's lang= wins. Elements carry data-i18n (text), data-i18n-label (aria-label)
// or data-i18n-title (title).
const STRINGS = {
  en: {
    title: 'geoslice', model: 'Model', language: 'Language', langSwitch: '中文', langSwitchLabel: 'Switch to Chinese',
    tabPlan: 'Plan', tabSection: 'Section', tab3d: '3D', views: 'Views',
    planElevation: 'Plan at elevation (m)', drawMode: 'Tap the plan to', modeQuery: 'Query', modeLine: 'Line A-B-C', modeNS: 'N-S', modeEW: 'E-W',
    modeAz: 'Azimuth', modeSlice: 'Slice', azimuth: 'Azimuth (°)', sliceElevation: 'Slice elevation (m)',
    vx: 'Vertical exaggeration', cut: 'Cut section', undo: 'Undo point', clear: 'Clear line',
    hintLine: 'Tap the map to add points A, B, C…, then Cut. Query asks what lies under a tap; a long-press gives a borehole.',
    hintPoint: 'Tap the map to place the section through that point.', hintSlice: 'Set the elevation, then Cut.',
    points: (n) => `${n} point${n === 1 ? '' : 's'}`, lineLength: (m) => `${m} m`, goto: 'Go to: easting, northing or lon, lat', gotoGo: 'Go', locate: 'My position',
    locateFailed: (m) => `My position: ${m}`,
    gotoBad: 'Go to: give two numbers, easting, northing (m) or lon, lat (°)',
    gotoNoGk: 'Go to: lon, lat needs a CGCS2000 Gauss-Kruger model here; give easting, northing',
    gotoOutside: (x, y, b) => `Go to: ${x}, ${y} lies outside the model (x ${b[0]}..${b[1]}, y ${b[2]}..${b[3]})`,
    measure: 'Measure', alongLine: 'apparent thickness along it',
    measureHint: 'Tap two points on the section: their true distance, and on a vertical section the apparent dip, whatever the exaggeration.',
    measured: (m, dip) => `Distance ${m} m (true)` + (dip == null ? '' : ` · apparent dip ${dip}°`), through: (x, y) => `through ${x}, ${y}`,
    noSection: 'No section yet: draw one on the plan.', sectionOf: 'Section',
    plDip: 'Dip (°)', plAz: 'Strike azimuth (°)', plOffset: 'Offset from centre (m)', resetCam: 'Reset view',
    moveHandle: 'Move the plane (drag, or arrow keys)', rotateHandle: 'Rotate the plane (drag, or arrow keys)',
    view3d: '3D view of the model cut by the plane; drag to orbit, pinch or wheel to zoom, tap to query',
    profile: 'Profile of the plane', profileAlt: 'Section along the current plane; tap to query',
    answer: 'Answer', legend: 'Legend', borehole: 'Borehole', copy: 'Copy', copied: 'Copied',
    f_id: 'Record id', f_name: 'Name', f_kind: 'Kind', f_lithology: 'Lithology', f_age: 'Age', f_era: 'Era',
    f_colour: 'Colour', f_colour_source: 'Colour from', f_name_source: 'Name from', f_density: 'Density (t/m³)',
    f_grade: 'Grade', f_grade_unit: 'Grade unit',
    tapHint: 'Tap a section, the plan or the 3D view to ask what lies there.',
    noGeology: 'No geology at this point', unit: 'Unit', body: 'Body', world: 'World point', crs: 'CRS',
    easting: 'Easting', northing: 'Northing', zone: 'Zone', lon: 'Longitude', lat: 'Latitude', elevation: 'Elevation',
    distance: 'Distance along section', distanceEye: 'Distance from the eye', source: 'Source', pixel: 'Pixel',
    attributes: 'Attributes', lithology: 'Lithology', age: 'Age', colour: 'Colour', name: 'Name',
    loading: 'Loading…', loadingModels: 'Loading the models…', loadingModel: (id) => `Loading ${id}…`, modelChanged: 'The model was baked again on the server: reloading this view…', failedCut: (m) => `Cut rejected: ${m}`, cutWhat: 'Cut', planWhat: 'Plan',
    unreachable: (what) => `${what}: cannot reach the server; trying again when it answers…`,
    serverAway: (what, m) => `${what}: the server is unavailable (${m}); trying again when it answers…`,
    rejected: (what, m) => `${what} rejected: ${m}`, failedQuery: (m) => `Query failed: ${m}`,
    failedModel: (m) => `Could not load the model: ${m}`, failedBorehole: (m) => `Borehole failed: ${m}`,
    failed3d: (m) => `3D view failed: ${m}`, tilesFailed: (n) => `${n} tile(s) could not be loaded after retries.`,
    retry: 'Retry', retrying: (n) => `Server busy, retrying ${n} tile(s)…`,
    bhHint: 'Long-press the plan or a section for a virtual borehole.', collar: 'Collar', depth: 'Depth from collar (m)',
    faults: 'Faults crossed', none: 'none', bhAt: (x, y) => `Borehole at ${x}, ${y}`,
    export: 'Export', exportPng: 'PNG', exportSvg: 'SVG', exportGeojson: 'GeoJSON', exportDxf: 'DXF', exportPdf: 'PDF',
    permalink: 'Copy link', linkCopied: 'Link copied', scale: 'Scale', metres: 'm', vxShown: (k) => `vx ${k}×`,
    upPlaneAxis: 'Up the plane (m)', elevAxis: 'Elevation (m)', distAxis: 'Distance (m)', eastAxis: 'Easting (m)', northAxis: 'Northing (m)',
    noModels: 'The server has no models.', zoomIn: 'Zoom in', zoomOut: 'Zoom out', bend: 'bend',
    needKey: (m) => `${m}. This server needs an API key: open this page with #key=YOUR_KEY after its address.`,
    closeSheet: 'Close', colourBy: 'Colour the block model by', blockLegend: 'Block-model colours',
    showAll: 'Show all units', units3d: 'Units shown in 3D', addPlane: 'Add plane', maxPlanes: 'A view takes at most six planes',
    planeN: (n, az, dip, off) => `Plane ${n}: strike ${az}°, dip ${dip}°, offset ${off} m`, removePlane: (n) => `Remove plane ${n}`,
    cut3d: 'The planes remove', cutUnion: 'what any plane removes', cutIntersection: 'only what every plane removes',
    showContext: 'Leases and workings', contextNotLoaded: (m) => `Context layer not loaded: ${m}`,
    showHoles: 'Drillholes', holeWindow: 'Drillholes within (m)', holeColour: 'Colour holes by', holeColourNone: 'one colour',
    holeLegend: 'Drillhole colours', holesBy: 'Holes by', holesNotLoaded: (m) => `Drillholes not loaded: ${m}`,
    holeTitle: (id) => `Drillhole ${id}`, logged: 'Logged', modelUnits: 'Model', holeDepth: 'Depth', agrees: 'Model agrees with the log',
    holeOffset: 'Off the section', inFront: 'in front', behind: 'behind', modelHere: 'Model here', stripLog: 'Strip log',
    noCodes: 'no logged unit codes', sectionAlong: 'Section along this hole', alongHole: (id) => `Along ${id}`,
    savedSections: 'Saved sections', savedPick: 'Open a saved section…', saveName: 'Save this section as', save: 'Save',
    saveNeedsName: 'Save: give the section a name', saveFailed: (m) => `Save failed: ${m}`, savedAs: (n) => `Saved as “${n}”`,
  },
  zh: {
    title: 'geoslice', model: '模型', language: '语言', langSwitch: 'English', langSwitchLabel: '切换到英文',
    tabPlan: '平面', tabSection: '剖面', tab3d: '三维', views: '视图',
    planElevation: '平面图高程（米）', drawMode: '点击平面图以', modeQuery: '查询', modeLine: '折线 A-B-C', modeNS: '南北', modeEW: '东西',
    modeAz: '方位角', modeSlice: '水平切片', azimuth: '方位角（°）', sliceElevation: '切片高程（米）',
    vx: '垂向放大倍数', cut: '生成剖面', undo: '撤销一点', clear: '清除折线',
    hintLine: '点击地图依次添加 A、B、C… 点，然后生成剖面。选“查询”后点击即查询；长按生成钻孔。',
    hintPoint: '点击地图，剖面将通过该点。', hintSlice: '设置高程，然后生成剖面。',
    points: (n) => `${n} 个点`, lineLength: (m) => `${m} 米`, goto: '定位：东坐标, 北坐标 或 经度, 纬度', gotoGo: '定位', locate: '我的位置',
    locateFailed: (m) => `我的位置：${m}`,
    gotoBad: '定位：请输入两个数，东坐标, 北坐标（米）或 经度, 纬度（度）',
    gotoNoGk: '定位：经纬度仅适用于 CGCS2000 高斯-克吕格模型；请输入东坐标, 北坐标',
    gotoOutside: (x, y, b) => `定位：${x}, ${y} 在模型范围之外（x ${b[0]}..${b[1]}，y ${b[2]}..${b[3]}）`,
    measure: '量测', alongLine: '沿线视厚度',
    measureHint: '在剖面上点两点：给出真实距离；直立剖面另给视倾角，与垂直夸张无关。',
    measured: (m, dip) => `距离 ${m} 米（真实）` + (dip == null ? '' : ` · 视倾角 ${dip}°`), through: (x, y) => `通过 ${x}, ${y}`,
    noSection: '尚无剖面：请在平面图上绘制。', sectionOf: '剖面',
    plDip: '倾角（°）', plAz: '走向方位角（°）', plOffset: '距中心偏移（米）', resetCam: '重置视图',
    moveHandle: '移动剖切面（拖动或方向键）', rotateHandle: '旋转剖切面（拖动或方向键）',
    view3d: '被剖切面切开的模型三维视图；拖动旋转，双指或滚轮缩放，点击查询',
    profile: '剖切面剖面图', profileAlt: '当前剖切面的剖面；点击查询',
    answer: '查询结果', legend: '图例', borehole: '钻孔', copy: '复制', copied: '已复制',
    f_id: '记录编号', f_name: '名称', f_kind: '类型', f_lithology: '岩性', f_age: '时代', f_era: '代',
    f_colour: '颜色', f_colour_source: '颜色来源', f_name_source: '名称来源', f_density: '密度（t/m³）',
    f_grade: '品位', f_grade_unit: '品位单位',
    v_stratum: '地层', v_orebody: '矿体', v_fault: '断层', v_intrusion: '侵入体', v_dyke: '岩脉', v_vein: '矿脉',
    v_unit: '单元', v_surface: '界面', v_generator: '生成器', v_sidecar: '属性文件', v_palette: '调色板',
    v_model: '模型文件', v_file: '模型文件', v_ray: '射线求交', 'v_id-buffer': '编号缓冲区',
    v_Paleozoic: '古生代', v_Mesozoic: '中生代', v_Cenozoic: '新生代', v_Precambrian: '前寒武纪',
    tapHint: '点击剖面、平面图或三维视图，查询该处地质。',
    noGeology: '此处无地质体', unit: '地层单元', body: '地质体', world: '世界坐标', crs: '坐标系',
    easting: '东坐标', northing: '北坐标', zone: '带号', lon: '经度', lat: '纬度', elevation: '高程',
    distance: '沿剖面距离', distanceEye: '距视点距离', source: '来源', pixel: '像素',
    attributes: '属性', lithology: '岩性', age: '时代', colour: '颜色', name: '名称',
    loading: '加载中…', loadingModels: '正在加载模型列表…', loadingModel: (id) => `正在加载 ${id}…`, modelChanged: '服务器上的模型已重新烘焙：正在重新加载此视图…', failedCut: (m) => `剖面被拒绝：${m}`, cutWhat: '剖切', planWhat: '平面图',
    unreachable: (what) => `${what}：无法连接服务器；服务器恢复后自动重试…`,
    serverAway: (what, m) => `${what}：服务器暂不可用（${m}）；服务器恢复后自动重试…`,
    rejected: (what, m) => `${what}被拒绝：${m}`, failedQuery: (m) => `查询失败：${m}`,
    failedModel: (m) => `无法加载模型：${m}`, failedBorehole: (m) => `钻孔失败：${m}`,
    failed3d: (m) => `三维视图失败：${m}`, tilesFailed: (n) => `${n} 个瓦片多次重试后仍无法加载。`,
    retry: '重试', retrying: (n) => `服务器繁忙，正在重试 ${n} 个瓦片…`,
    bhHint: '在平面图或剖面上长按，生成虚拟钻孔。', collar: '孔口', depth: '孔深（米，自孔口）',
    faults: '穿过的断层', none: '无', bhAt: (x, y) => `钻孔位于 ${x}, ${y}`,
    export: '导出', exportPng: 'PNG', exportSvg: 'SVG', exportGeojson: 'GeoJSON', exportDxf: 'DXF', exportPdf: 'PDF',
    permalink: '复制链接', linkCopied: '链接已复制', scale: '比例尺', metres: '米', vxShown: (k) => `垂向放大 ${k}×`,
    upPlaneAxis: '沿剖切面向上（米）', elevAxis: '高程（米）', distAxis: '距离（米）', eastAxis: '东坐标（米）', northAxis: '北坐标（米）',
    noModels: '服务器上没有模型。', zoomIn: '放大', zoomOut: '缩小', bend: '拐点',
    needKey: (m) => `${m}。此服务器需要 API 密钥：请在本页地址后加上 #key=您的密钥 再打开。`,
    closeSheet: '关闭', colourBy: '块体模型着色依据', blockLegend: '块体模型颜色',
    showAll: '显示全部地层', units3d: '三维中显示的地层', addPlane: '添加剖切面', maxPlanes: '一个视图最多六个剖切面',
    planeN: (n, az, dip, off) => `剖切面 ${n}：走向 ${az}°，倾角 ${dip}°，偏移 ${off} 米`, removePlane: (n) => `移除剖切面 ${n}`,
    cut3d: '剖切面移除', cutUnion: '任一剖切面移除的部分', cutIntersection: '仅所有剖切面共同移除的部分',
    showContext: '矿权与工程', contextNotLoaded: (m) => `背景图层未加载：${m}`,
    showHoles: '钻孔', holeWindow: '显示剖面两侧钻孔（米）', holeColour: '钻孔着色依据', holeColourNone: '单一颜色',
    holeLegend: '钻孔图例', holesBy: '钻孔按', holesNotLoaded: (m) => `钻孔未加载：${m}`,
    holeTitle: (id) => `钻孔 ${id}`, logged: '编录', modelUnits: '模型', holeDepth: '孔深', agrees: '模型与编录吻合',
    holeOffset: '距剖面', inFront: '（剖面前方）', behind: '（剖面后方）', modelHere: '此处模型', stripLog: '钻孔柱状图',
    noCodes: '无编录地层代码', sectionAlong: '沿此钻孔作剖面', alongHole: (id) => `沿 ${id}`,
    savedSections: '已存剖面', savedPick: '打开已存剖面…', saveName: '剖面另存为', save: '保存',
    saveNeedsName: '保存：请为剖面命名', saveFailed: (m) => `保存失败：${m}`, savedAs: (n) => `已保存为“${n}”`,
  },
};

let lang = 'en';

export function initialLanguage(hashLang) {
  if (hashLang && STRINGS[hashLang]) return hashLang;
  try {
    const saved = localStorage.getItem('geoslice.lang');
    if (saved && STRINGS[saved]) return saved;
  } catch (_) { /* storage may be disabled */ }
  for (const l of navigator.languages || [navigator.language || 'en']) {
    if (/^zh\b/i.test(l)) return 'zh';
    if (/^en\b/i.test(l)) return 'en';
  }
  return 'en';
}

export function setLanguage(l, save = false) {
  lang = STRINGS[l] ? l : 'en';
  if (save) try { localStorage.setItem('geoslice.lang', lang); } catch (_) { /* ignore */ }
  document.documentElement.lang = lang === 'zh' ? 'zh-CN' : 'en';
  for (const e of document.querySelectorAll('[data-i18n]')) e.textContent = t(e.dataset.i18n);
  const sw = document.getElementById('lang');
  if (sw) sw.lang = lang === 'zh' ? 'en' : 'zh-CN';
  for (const e of document.querySelectorAll('[data-i18n-label]')) e.setAttribute('aria-label', t(e.dataset.i18nLabel));
  for (const e of document.querySelectorAll('[data-i18n-title]')) e.title = t(e.dataset.i18nTitle);
  for (const e of document.querySelectorAll('[data-i18n-alt]')) e.alt = t(e.dataset.i18nAlt);
}
export const language = () => lang;

// An attribute's label (the record's field names: id, kind, lithology, ...); a field this
// page does not know (a model's own attribute) keeps its name, which is data, not UI.
export function fieldName(k) {
  return STRINGS[lang][`f_${k}`] ?? STRINGS.en[`f_${k}`] ?? k;
}
// A value from a closed vocabulary (kind, era, where a colour or an answer came from) in
// the page's language; any other value as it is.
export function fieldValue(v) {
  return typeof v === 'string' ? STRINGS[lang][`v_${v}`] ?? v : v;
}
export function t(key, ...args) {
  const s = STRINGS[lang][key] ?? STRINGS.en[key] ?? key;
  return typeof s === 'function' ? s(...args) : s;
}
