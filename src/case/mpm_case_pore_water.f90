!> The `pore_water` key of a case: soils saturated with pore water (their porosity and
!> hydraulic conductivity), the water's density and bulk modulus, the phreatic level of the
!> initial hydrostatic pressures and the drainage of the domain's faces.
!>
!> A material listed here is a saturated soil: its `rho` is the saturated density, its law
!> works on the effective stress, and each of its particles carries a pore pressure
!> (mpm_pore_water). The section writes the porosity, conductivity and water properties into
!> the materials it lists (`material_spec_type`), so the stability limits of the time step
!> (mpm_case_stability) see them; everything else stays here.
module mpm_case_pore_water
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: int_text, fmt_real
    use mpm_case_cursor, only: cursor_type
    use mpm_case_materials, only: material_spec_type, material_index, material_list
    use mpm_case_domain, only: face_keys
    implicit none
    private
    public :: pore_water_section_type, read_pore_water, pore_water_keys, pore_material_keys, &
        pore_face_pressure_keys, pore_water_summary, hydrostatic_pressure
    public :: drain_none, drain_drained, drain_pressure, drain_names

    character(len=*), parameter :: pore_water_keys(*) = [character(len=14) :: "density", &
        "bulk_modulus", "materials", "phreatic_level", "faces"]
        !! keys of `pore_water`
    character(len=*), parameter :: pore_material_keys(*) = [character(len=12) :: "material", &
        "porosity", "permeability"]
        !! keys of an entry of `pore_water.materials`
    character(len=*), parameter :: pore_face_pressure_keys(*) = [character(len=8) :: "pressure"]
        !! keys of a face of `pore_water.faces` given as an object

    ! The drainage of a face
    integer, parameter :: drain_none = 0
        !! an impermeable face, which no water crosses (the default)
    integer, parameter :: drain_drained = 1
        !! a drained face, whose pore pressure is the hydrostatic one of the phreatic level
        !! (zero above the level, or everywhere without one)
    integer, parameter :: drain_pressure = 2
        !! a prescribed pore pressure
    character(len=*), parameter :: drain_names(0:1) = [character(len=11) :: "impermeable", &
        "drained"]
        !! names of the faces written as a string

    !> `pore_water`: the pore water of the saturated soils.
    type :: pore_water_section_type
        logical :: on = .false.
            !! some material of the case is a saturated soil
        real(wp) :: density = 1000.0_wp
            !! density of the pore water rho_w [kg/m3]
        real(wp) :: bulk_modulus = 2.2e9_wp
            !! bulk modulus of the pore water K_w [Pa]
        logical :: has_level = .false.
            !! `phreatic_level` given
        real(wp) :: level = 0.0_wp
            !! height of the water table on the vertical axis (y in 2D, z in 3D) [m]
        integer :: face(2, 3) = drain_none
            !! drainage of each face (side, axis): drain_none, drain_drained, drain_pressure
        real(wp) :: face_pressure(2, 3) = 0.0_wp
            !! the pore pressure of a drain_pressure face [Pa]
    end type pore_water_section_type

contains

    !> `pore_water`: the water, the saturated materials, the phreatic level and the faces.
    subroutine read_pore_water(root, dim, gravity, materials, water, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        integer, intent(in) :: dim
            !! space dimensions
        real(wp), intent(in) :: gravity(3)
            !! gravitational acceleration [m/s2]
        type(material_spec_type), intent(inout) :: materials(:)
            !! the materials; the listed ones get their porosity, conductivity and water
        type(pore_water_section_type), intent(out) :: water
            !! the section
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: cur, list, item
        character(len=:), allocatable :: name
        integer :: i, m
        integer, allocatable :: listed(:)
        logical :: found
        real(wp) :: porosity, permeability

        call root%get_section("pore_water", pore_water_keys, cur, error, found=found)
        if (allocated(error) .or. .not. found) return
        water%on = .true.
        call cur%get_real("density", water%density, error, above=0.0_wp, unit="kg/m3")
        if (allocated(error)) return
        call cur%get_real("bulk_modulus", water%bulk_modulus, error, above=0.0_wp, unit="Pa")
        if (allocated(error)) return
        call cur%get_list("materials", "saturated material", list, error)
        if (allocated(error)) return
        allocate (listed(list%size()))
        do i = 1, list%size()
            item = list%item(i)
            call item%check_type("object", 'an object {"material": ..., "porosity": ..., ' &
                //'"permeability": ...}', error)
            if (allocated(error)) return
            call item%check_keys(pore_material_keys, error)
            if (allocated(error)) return
            call item%get_string("material", name, error, required=.true.)
            if (allocated(error)) return
            m = material_index(materials, name)
            if (m == 0) then
                call item%fail(error, item%key_path("material")//' = "'//name//'" is not a ' &
                    //"material of the case: must be one of "//material_list(materials))
                return
            end if
            if (any(listed(:i - 1) == m)) then
                call item%fail(error, item%key_path("material")//' = "'//name//'" is listed ' &
                    //"twice; give each saturated material once")
                return
            end if
            listed(i) = m
            if (allocated(materials(m)%law)) then
                if (materials(m)%law%rigid()) then
                    call item%fail(error, item%key_path("material")//' = "'//name//'" is ' &
                        //"a rigid body, which holds no pore water; list soils only")
                    return
                end if
            end if
            porosity = 0.0_wp
            call item%get_real("porosity", porosity, error, required=.true., above=0.0_wp, &
                below=1.0_wp)
            if (allocated(error)) return
            permeability = 0.0_wp
            call item%get_real("permeability", permeability, error, required=.true., &
                at_least=0.0_wp, unit="m/s")
            if (allocated(error)) return
            if (materials(m)%density <= porosity*water%density) then
                call item%fail(error, "materials["//int_text(m)//'] "'//name//'" has rho = ' &
                    //fmt_real(materials(m)%density)//" kg/m3, which is the density of the " &
                    //"saturated soil: it must exceed porosity x pore_water.density = " &
                    //fmt_real(porosity*water%density)//" kg/m3")
                return
            end if
            materials(m)%porosity = porosity
            materials(m)%permeability = permeability
            materials(m)%water_bulk_modulus = water%bulk_modulus
            materials(m)%water_density = water%density
        end do
        if (cur%has("phreatic_level")) then
            if (gravity(dim) >= 0.0_wp) then
                call cur%fail(error, cur%key_path("phreatic_level")//" sets hydrostatic " &
                    //"pressures below the water table, which need gravity pointing down the " &
                    //"vertical axis ("//trim(merge("y", "z", dim == 2))//"): its " &
                    //"component "//fmt_real(gravity(dim))//" m/s2 must be < 0")
                return
            end if
            water%has_level = .true.
            call cur%get_real("phreatic_level", water%level, error, unit="m")
            if (allocated(error)) return
        end if
        call read_faces(cur, dim, water, error)
    end subroutine read_pore_water

    !> `pore_water.faces`: per face "impermeable" (the default), "drained" or
    !> {"pressure": p}.
    subroutine read_faces(cur, dim, water, error)
        type(cursor_type), intent(in) :: cur
            !! the pore_water object
        integer, intent(in) :: dim
            !! space dimensions
        type(pore_water_section_type), intent(inout) :: water
            !! the section
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: faces, face
        logical :: found
        integer :: k, axis, side

        call cur%get_section("faces", face_keys, faces, error, found=found)
        if (allocated(error) .or. .not. found) return
        do k = 1, size(face_keys)
            axis = (k + 1)/2
            side = 2 - mod(k, 2)
            if (.not. faces%has(trim(face_keys(k)))) cycle
            if (axis > dim) then
                call faces%fail(error, faces%key_path(trim(face_keys(k)))//" is not " &
                    //"allowed in a 2D case (dimension = 2): a 2D domain has no z faces")
                return
            end if
            face = faces%child(trim(face_keys(k)))
            if (face%kind() == "object") then
                call face%check_keys(pore_face_pressure_keys, error)
                if (allocated(error)) return
                water%face(side, axis) = drain_pressure
                call face%get_real("pressure", water%face_pressure(side, axis), error, &
                    required=.true., unit="Pa")
                if (allocated(error)) return
            else
                call faces%get_choice(trim(face_keys(k)), drain_names, [drain_none, &
                    drain_drained], water%face(side, axis), error)
                if (allocated(error)) then
                    error%message = error%message//', or an object {"pressure": p} (a ' &
                        //"prescribed pore pressure [Pa])"
                    return
                end if
            end if
        end do
    end subroutine read_faces

    !> The hydrostatic pore pressure at x of the phreatic level [Pa]: rho_w g . (x - x_w)
    !> below the water table (x_w on it), zero above it and without a level.
    pure real(wp) function hydrostatic_pressure(water, dim, gravity, x)
        type(pore_water_section_type), intent(in) :: water
            !! the section
        integer, intent(in) :: dim
            !! space dimensions
        real(wp), intent(in) :: gravity(3)
            !! gravitational acceleration [m/s2]
        real(wp), intent(in) :: x(:)
            !! position [m]

        hydrostatic_pressure = 0.0_wp
        if (.not. water%has_level) return
        hydrostatic_pressure = water%density*max(0.0_wp, &
            dot_product(gravity(1:dim), x(1:dim)) - gravity(dim)*water%level)
    end function hydrostatic_pressure

    !> The lines of `--check` of the section: none without pore water.
    function pore_water_summary(water, materials) result(lines)
        type(pore_water_section_type), intent(in) :: water
            !! the section
        type(material_spec_type), intent(in) :: materials(:)
            !! the materials
        character(len=:), allocatable :: lines

        integer :: m, k, axis, side
        character(len=:), allocatable :: faces

        lines = ""
        if (.not. water%on) return
        lines = "pore water  rho_w = "//fmt_real(water%density)//" kg/m3, K_w = " &
            //fmt_real(water%bulk_modulus)//" Pa"
        if (water%has_level) lines = lines//", phreatic level "//fmt_real(water%level)//" m"
        do m = 1, size(materials)
            if (materials(m)%porosity <= 0.0_wp) cycle
            lines = lines//new_line("a")//'  saturated  "'//materials(m)%name//'": n = ' &
                //fmt_real(materials(m)%porosity)//", k = "//fmt_real(materials(m)%permeability) &
                //" m/s"
            if (materials(m)%permeability == 0.0_wp) lines = lines//" (undrained)"
        end do
        faces = ""
        do k = 1, size(face_keys)
            axis = (k + 1)/2
            side = 2 - mod(k, 2)
            select case (water%face(side, axis))
            case (drain_drained)
                faces = faces//" "//trim(face_keys(k))//" drained"
            case (drain_pressure)
                faces = faces//" "//trim(face_keys(k))//" p = "// &
                    fmt_real(water%face_pressure(side, axis))//" Pa"
            case default
                continue   ! impermeable: not listed
            end select
        end do
        if (len(faces) == 0) faces = " none (all impermeable)"
        lines = lines//new_line("a")//"  drained faces:"//faces
    end function pore_water_summary

end module mpm_case_pore_water
