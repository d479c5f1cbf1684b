!> The `materials` key of a case: the constitutive models and their parameters.
module mpm_case_materials
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: int_text, fmt_real, fmt_below, same
    use mpm_case_cursor, only: cursor_type
    implicit none
    private
    public :: material_spec_type, read_materials, material_keys, material_index, material_list
    public :: cone_plane_strain, cone_compression, cone_extension, cone_names
    public :: softening_none, softening_linear, softening_exponential, softening_names
    public :: model_choices, model_choice_codes, softening_keys, any_material_keys, degree

    ! Drucker-Prager cone matched to Mohr-Coulomb
    integer, parameter :: cone_plane_strain = 1  !! same collapse load in plane strain
    integer, parameter :: cone_compression = 2   !! outer cone: through the compression corners
    integer, parameter :: cone_extension = 3     !! inner cone: through the extension corners
    character(len=*), parameter :: cone_names(3) = [character(len=12) :: "plane_strain", &
        "compression", "extension"]

    ! Softening of strength parameters with the accumulated plastic shear strain
    integer, parameter :: softening_none = 0         !! constant strength
    integer, parameter :: softening_linear = 1       !! linear from peak to residual
    integer, parameter :: softening_exponential = 2  !! exponential decay to residual
    character(len=*), parameter :: softening_names(0:2) = [character(len=11) :: "none", &
        "linear", "exponential"]

    character(len=*), parameter :: elastic_keys(*) = [character(len=4) :: "name", "type", &
        "E", "nu", "rho"]
    character(len=*), parameter :: mohr_coulomb_keys(*) = [character(len=14) :: "name", &
        "type", "E", "nu", "rho", "phi", "c", "psi", "tension_cutoff", "softening", "separation"]
    character(len=*), parameter :: drucker_prager_keys(*) = [character(len=14) :: &
        mohr_coulomb_keys, "cone"]
    character(len=*), parameter :: newtonian_keys(*) = [character(len=12) :: "name", "type", &
        "rho", "viscosity", "bulk_modulus"]
    character(len=*), parameter :: any_material_keys(*) = [character(len=14) :: &
        drucker_prager_keys, "viscosity", "bulk_modulus"]
        !! keys of every material type, to tell a misplaced key from a misspelt one
    character(len=*), parameter :: softening_keys(*) = [character(len=12) :: "type", &
        "phi_residual", "c_residual", "psi_residual", "strain"]
    ! Material models (codes used only inside the reader; the case stores the model name)
    integer, parameter :: model_elastic = 1, model_mohr_coulomb = 2, model_drucker_prager = 3, &
        model_newtonian = 4, model_neo_hookean = 5
    character(len=*), parameter :: model_names(5) = [character(len=14) :: "linear_elastic", &
        "mohr_coulomb", "drucker_prager", "newtonian", "neo_hookean"]
        !! name stored in material_spec_type%type for each model code
    character(len=*), parameter :: model_choices(6) = [character(len=14) :: "linear_elastic", &
        "elastic", "mohr_coulomb", "drucker_prager", "newtonian", "neo_hookean"]
        !! names accepted for materials[i].type (aliases included)
    integer, parameter :: model_choice_codes(6) = [model_elastic, model_elastic, &
        model_mohr_coulomb, model_drucker_prager, model_newtonian, model_neo_hookean]

    real(wp), parameter :: degree = acos(-1.0_wp)/180.0_wp
        !! one degree [rad]: angles are given in degrees and stored in radians

    !> One material of the case. Which parameters are used depends on `type`.
    type :: material_spec_type
        character(len=:), allocatable :: name
            !! name used by bodies to refer to this material
        character(len=:), allocatable :: type
            !! constitutive model: "linear_elastic", "mohr_coulomb", "drucker_prager", "newtonian"
        real(wp) :: young = 0.0_wp
            !! Young's modulus E [Pa] (elastic and elasto-plastic types)
        real(wp) :: poisson = 0.0_wp
            !! Poisson's ratio nu [-] (elastic and elasto-plastic types)
        real(wp) :: density = 0.0_wp
            !! mass density rho [kg/m3]
        real(wp) :: friction = 0.0_wp
            !! peak friction angle phi [rad] (input in degrees)
        real(wp) :: cohesion = 0.0_wp
            !! peak cohesion c [Pa]
        real(wp) :: dilatancy = 0.0_wp
            !! peak dilatancy angle psi [rad] (input in degrees), 0 <= psi <= phi
        real(wp) :: tension_cutoff = -1.0_wp
            !! tensile strength: largest mean (DP) or principal (MC) stress allowed [Pa];
            !! negative when not given (then the apex of the cone, c / tan(phi), limits it)
        logical :: separation = .false.
            !! cohesionless separation: dilation at the stress-free apex opens the material,
            !! and compression closes it again before any stress builds (MC and DP, c = 0 or
            !! tension_cutoff = 0)
        integer :: softening = softening_none
            !! softening law of phi, c and psi with the plastic shear strain
        real(wp) :: friction_residual = 0.0_wp
            !! residual friction angle [rad] (softening only)
        real(wp) :: cohesion_residual = 0.0_wp
            !! residual cohesion [Pa] (softening only)
        real(wp) :: dilatancy_residual = 0.0_wp
            !! residual dilatancy angle [rad] (softening only)
        real(wp) :: softening_strain = 0.0_wp
            !! linear: plastic shear strain at which the residual values are reached;
            !! exponential: strain scale eta_0 in x = x_r + (x_p - x_r) exp(-eps_p / eta_0) [-]
        integer :: cone = cone_plane_strain
            !! Drucker-Prager cone matched to the Mohr-Coulomb parameters
        real(wp) :: viscosity = 0.0_wp
            !! dynamic viscosity mu of a Newtonian fluid [Pa s]
        real(wp) :: bulk_modulus = 0.0_wp
            !! bulk modulus K of a Newtonian fluid [Pa] (sets the pressure and the wave speed)
    end type material_spec_type

contains

    !> `materials`: a non-empty array of uniquely named materials. The keys allowed in a
    !> material depend on its type, so the type is read before the keys are checked.
    subroutine read_materials(root, materials, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        type(material_spec_type), allocatable, intent(out) :: materials(:)
            !! the materials, in file order
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: list, item
        integer :: i, j, model

        call root%get_list("materials", "material", list, error)
        if (allocated(error)) return
        allocate (materials(list%size()))
        do i = 1, size(materials)
            item = list%item(i)
            call item%check_type("object", "an object", error)
            if (allocated(error)) return
            call read_material_type(item, model, error)
            if (allocated(error)) return
            associate (mat => materials(i))
                mat%type = trim(model_names(model))
                call item%get_string("name", mat%name, error, required=.true.)
                if (allocated(error)) return
                do j = 1, i - 1
                    if (same(materials(j)%name, mat%name)) then
                        call item%fail(error, item%path//'.name = "'//mat%name//'" is ' &
                            //"already the name of materials["//int_text(j)//"]; material " &
                            //"names must be unique")
                        return
                    end if
                end do
                if (model == model_newtonian) then
                    call read_newtonian(item, mat, error)
                    if (allocated(error)) return
                else
                    call read_elasticity(item, mat, error)
                    if (allocated(error)) return
                    if (model == model_mohr_coulomb .or. model == model_drucker_prager) then
                        call read_strength(item, model, mat, error)
                        if (allocated(error)) return
                    end if
                end if
            end associate
        end do
    end subroutine read_materials

    !> `materials[i].type`, then the keys of a material of that type.
    subroutine read_material_type(item, model, error)
        type(cursor_type), intent(in) :: item
            !! the material object
        integer, intent(out) :: model
            !! model code (model_elastic, ...)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=:), allocatable :: owner

        model = 0
        if (.not. item%has("type")) then
            ! a misspelt "type" is reported as such rather than as a missing type
            call item%check_keys(any_material_keys, error)
            if (allocated(error)) return
        end if
        call item%get_choice("type", model_choices, model_choice_codes, model, &
            error, required=.true.)
        if (allocated(error)) return
        owner = "a "//trim(model_names(model))//" material"
        call item%check_keys(material_keys(model), error, owner, any_material_keys)
    end subroutine read_material_type

    !> Keys of a material of one model (the reader's check and `case_key_paths` both use it).
    pure function material_keys(model) result(keys)
        integer, intent(in) :: model
            !! model code (model_elastic, ...)
        character(len=len(any_material_keys)), allocatable :: keys(:)

        select case (model)
        case (model_elastic, model_neo_hookean)
            keys = elastic_keys
        case (model_mohr_coulomb)
            keys = mohr_coulomb_keys
        case (model_drucker_prager)
            keys = drucker_prager_keys
        case default
            keys = newtonian_keys
        end select
    end function material_keys

    !> Elastic parameters of a solid: `E`, `nu`, `rho`.
    subroutine read_elasticity(item, mat, error)
        type(cursor_type), intent(in) :: item
            !! the material object
        type(material_spec_type), intent(inout) :: mat
            !! material being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        call item%get_real("E", mat%young, error, required=.true., above=0.0_wp, &
            unit="Pa")
        if (allocated(error)) return
        call item%get_real("nu", mat%poisson, error, required=.true., &
            at_least=0.0_wp, below=0.5_wp)
        if (allocated(error)) return
        call item%get_real("rho", mat%density, error, required=.true., &
            above=0.0_wp, unit="kg/m3")
    end subroutine read_elasticity

    !> Strength of a Mohr-Coulomb or Drucker-Prager material: `phi`, `c`, `psi`,
    !> `tension_cutoff`, `softening` and (Drucker-Prager) `cone`. Angles are read in degrees
    !> and stored in radians.
    subroutine read_strength(item, model, mat, error)
        type(cursor_type), intent(in) :: item
            !! the material object
        integer, intent(in) :: model
            !! model_mohr_coulomb or model_drucker_prager
        type(material_spec_type), intent(inout) :: mat
            !! material being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=:), allocatable :: family, limit
        logical :: found
        real(wp) :: phi, c, psi, cutoff, apex

        family = "Mohr-Coulomb"
        if (model == model_drucker_prager) family = "Drucker-Prager"
        phi = 0.0_wp
        c = 0.0_wp
        psi = 0.0_wp
        cutoff = -1.0_wp
        call item%get_real("phi", phi, error, required=.true., at_least=0.0_wp, &
            below=90.0_wp, unit="deg")
        if (allocated(error)) return
        call item%get_real("c", c, error, at_least=0.0_wp, unit="Pa")
        if (allocated(error)) return
        if (phi == 0.0_wp .and. c == 0.0_wp) then
            call item%fail(error, item%path//".phi = 0 and "//item%path//".c = 0: a "//family &
                //" material with phi = 0 and c = 0 has no strength; use a newtonian fluid, " &
                //"or give phi > 0 [deg] or c > 0 [Pa]")
            return
        end if
        call item%get_real("psi", psi, error, at_least=0.0_wp, unit="deg")
        if (allocated(error)) return
        if (psi > phi) then
            call item%fail(error, item%path//".psi = "//fmt_real(psi)//" deg is above " &
                //item%path//".phi = "//fmt_real(phi)//" deg: the dilatancy angle must be >= 0 " &
                //"and <= phi = "//fmt_real(phi)//" [deg]")
            return
        end if
        call item%get_real("tension_cutoff", cutoff, error, at_least=0.0_wp, &
            unit="Pa", found=found)
        if (allocated(error)) return
        if (found .and. phi > 0.0_wp) then
            ! the cone ends at the mean stress c / tan(phi): no stress state lies beyond it
            apex = c/tan(phi*degree)
            if (cutoff > apex) then
                limit = fmt_below(apex, cutoff)
                call item%fail(error, item%path//".tension_cutoff = "//fmt_real(cutoff) &
                    //" Pa is above the apex of the yield surface, c / tan(phi) = "//limit &
                    //" Pa (c = "//fmt_real(c)//" Pa, phi = "//fmt_real(phi)//" deg): must " &
                    //"be >= 0 and <= "//limit//" [Pa]")
                return
            end if
        end if
        mat%friction = phi*degree
        mat%cohesion = c
        mat%dilatancy = psi*degree
        mat%tension_cutoff = cutoff
        call item%get_bool("separation", mat%separation, error)
        if (allocated(error)) return
        if (mat%separation .and. c > 0.0_wp .and. cutoff /= 0.0_wp) then
            call item%fail(error, item%path//".separation = true needs a stress-free apex: " &
                //"c = "//fmt_real(c)//" Pa here; give c = 0 or tension_cutoff = 0, or set " &
                //"separation to false")
            return
        end if
        call read_softening(item, phi, c, psi, mat, error)
        if (allocated(error)) return
        if (model == model_drucker_prager) then
            call item%get_choice("cone", cone_names, [cone_plane_strain, &
                cone_compression, cone_extension], mat%cone, error)
        end if
    end subroutine read_strength

    !> `materials[i].softening`: residual strength and the plastic shear strain that reaches
    !> it. Residual values default to the peak values (psi_residual to 0) and never exceed them.
    subroutine read_softening(item, phi, c, psi, mat, error)
        type(cursor_type), intent(in) :: item
            !! the material object
        real(wp), intent(in) :: phi
            !! peak friction angle [deg]
        real(wp), intent(in) :: c
            !! peak cohesion [Pa]
        real(wp), intent(in) :: psi
            !! peak dilatancy angle [deg]
        type(material_spec_type), intent(inout) :: mat
            !! material being resolved (peak values set)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: softening
        character(len=:), allocatable :: spath
        logical :: found
        integer :: k
        real(wp) :: phi_r, c_r, psi_r

        ! without softening the residual values are the peak values
        mat%softening = softening_none
        mat%friction_residual = mat%friction
        mat%cohesion_residual = mat%cohesion
        mat%dilatancy_residual = mat%dilatancy
        call item%get_section("softening", softening_keys, softening, error, &
            found=found)
        if (allocated(error) .or. .not. found) return
        spath = softening%path
        call softening%get_choice("type", softening_names, [softening_none, &
            softening_linear, softening_exponential], mat%softening, error, required=.true.)
        if (allocated(error)) return
        if (mat%softening == softening_none) then
            do k = 2, size(softening_keys)
                if (softening%has(trim(softening_keys(k)))) then
                    call item%fail(error, spath//"."//trim(softening_keys(k)) &
                        //' only applies to softening.type = "linear" or "exponential" ' &
                        //'(here "none"); remove it')
                    return
                end if
            end do
            return
        end if
        phi_r = phi
        c_r = c
        psi_r = 0.0_wp
        call softening%get_real("phi_residual", phi_r, error, at_least=0.0_wp, &
            unit="deg")
        if (allocated(error)) return
        call check_residual(item, spath//".phi_residual", phi_r, item%path//".phi", phi, "deg", error)
        if (allocated(error)) return
        call softening%get_real("c_residual", c_r, error, at_least=0.0_wp, &
            unit="Pa")
        if (allocated(error)) return
        call check_residual(item, spath//".c_residual", c_r, item%path//".c", c, "Pa", error)
        if (allocated(error)) return
        call softening%get_real("psi_residual", psi_r, error, at_least=0.0_wp, &
            unit="deg")
        if (allocated(error)) return
        call check_residual(item, spath//".psi_residual", psi_r, item%path//".psi", psi, "deg", error)
        if (allocated(error)) return
        if (psi_r > phi_r) then
            call item%fail(error, spath//".psi_residual = "//fmt_real(psi_r)//" deg " &
                //"is above the residual friction angle "//fmt_real(phi_r)//" deg: the " &
                //"dilatancy angle must be >= 0 and <= phi, also at residual strength [deg]")
            return
        end if
        if (phi_r == 0.0_wp .and. c_r == 0.0_wp) then
            call item%fail(error, spath//": phi_residual = 0 and c_residual = 0 leave " &
                //"no strength once softened; keep phi_residual > 0 [deg] or c_residual > 0 " &
                //"[Pa] (a material without strength is a newtonian fluid)")
            return
        end if
        call softening%get_real("strain", mat%softening_strain, error, &
            required=.true., above=0.0_wp)
        if (allocated(error)) return
        mat%friction_residual = phi_r*degree
        mat%cohesion_residual = c_r
        mat%dilatancy_residual = psi_r*degree
    end subroutine read_softening

    !> Refuse a residual strength parameter above its peak value.
    subroutine check_residual(item, key, residual, peak_key, peak, unit, error)
        type(cursor_type), intent(in) :: item
            !! the material object
        character(len=*), intent(in) :: key
            !! full key path of the residual value
        real(wp), intent(in) :: residual
            !! residual value [unit]
        character(len=*), intent(in) :: peak_key
            !! full key path of the peak value
        real(wp), intent(in) :: peak
            !! peak value [unit]
        character(len=*), intent(in) :: unit
            !! unit of both values
        type(error_type), allocatable, intent(out) :: error
            !! set when residual > peak

        if (residual > peak) then
            call item%fail(error, key//" = "//fmt_real(residual)//" "//unit//" is " &
                //"above the peak value "//peak_key//" = "//fmt_real(peak)//" "//unit &
                //": residual strength above peak; must be >= 0 and <= "//fmt_real(peak) &
                //" ["//unit//"]")
        end if
    end subroutine check_residual

    !> A Newtonian fluid: `rho`, `viscosity`, `bulk_modulus`.
    subroutine read_newtonian(item, mat, error)
        type(cursor_type), intent(in) :: item
            !! the material object
        type(material_spec_type), intent(inout) :: mat
            !! material being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        call item%get_real("rho", mat%density, error, required=.true., &
            above=0.0_wp, unit="kg/m3")
        if (allocated(error)) return
        call item%get_real("viscosity", mat%viscosity, error, required=.true., &
            at_least=0.0_wp, unit="Pa s")
        if (allocated(error)) return
        call item%get_real("bulk_modulus", mat%bulk_modulus, error, &
            required=.true., above=0.0_wp, unit="Pa")
    end subroutine read_newtonian

    !> Index of the material called `name`, 0 when there is none.
    pure integer function material_index(materials, name)
        type(material_spec_type), intent(in) :: materials(:)
            !! materials of the case
        character(len=*), intent(in) :: name
            !! name to find

        do material_index = 1, size(materials)
            if (same(materials(material_index)%name, name)) return
        end do
        material_index = 0
    end function material_index

    !> The material names, quoted and separated by commas.
    pure function material_list(materials) result(list)
        type(material_spec_type), intent(in) :: materials(:)
            !! materials of the case
        character(len=:), allocatable :: list

        integer :: m

        list = ""
        do m = 1, size(materials)
            if (m > 1) list = list//", "
            list = list//'"'//materials(m)%name//'"'
        end do
    end function material_list

end module mpm_case_materials
